//! A trained arousal network as stored in a weights file, and whole-recording inference
//! (sliding 20-step windows, half overlapping, averaged where they overlap).

use std::collections::HashMap;
use std::path::Path;

use candle_core::{DType, Device, Tensor};
use candle_nn::{VarBuilder, VarMap};
use ndarray::ArrayView2;
use net_core::file::{self, TensorFile};
use net_core::frames::check_mel;
use net_core::vars;

use crate::error::{EmotionError, Result};
use crate::features::emotion_mel;
use crate::model::{Config, EmotionNet};

/// Value of the `format` metadata entry of emotion-net weights.
pub const FORMAT_NAME: &str = "violin-skeleton/emotion-net";
/// Current weights format version.
pub const FORMAT_VERSION: u32 = 1;

/// The shipped default weights (see the crate README for how they were trained).
static PRETRAINED: &[u8] = include_bytes!("../weights/emotion-net.safetensors");

/// Arousal estimation: the network with its normalisation.
///
/// ```no_run
/// let est = emotion_net::ArousalEstimator::pretrained()?;
/// let audio = dsp_mel::load_audio("take1.wav")?;
/// let arousal = est.predict_audio(&audio)?; // 2 values per second, in [-1, 1]
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct ArousalEstimator {
    net: EmotionNet,
    tensors: Vec<(String, Tensor)>,
    training: String,
}

/// The variable names and shapes a network of `cfg` has.
pub fn expected_shapes(cfg: &Config) -> Result<Vec<(String, Vec<usize>)>> {
    let varmap = VarMap::new();
    EmotionNet::new(
        cfg,
        VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu),
    )?;
    Ok(vars::var_shapes(&varmap))
}

impl ArousalEstimator {
    /// The embedded default weights.
    pub fn pretrained() -> Result<Self> {
        Self::from_bytes(PRETRAINED, Path::new("<embedded emotion-net weights>"))
    }

    /// Reads weights written by [`ArousalEstimator::save`]; rejects other networks, other
    /// format versions and tensors whose shapes do not match the stored configuration.
    pub fn load(path: &Path) -> Result<Self> {
        Self::from_file(file::read(path)?, path)
    }

    /// [`ArousalEstimator::load`] from bytes; `path` names them in errors.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self> {
        Self::from_file(file::decode(bytes, path)?, path)
    }

    fn from_file(file: TensorFile, path: &Path) -> Result<Self> {
        file.check_format(path, FORMAT_NAME, FORMAT_VERSION)?;
        let cfg: Config = file.meta_json("config", path)?;
        cfg.validate().map_err(|e| EmotionError::weights(path, e))?;
        let tensors = file.take_expected(path, &expected_shapes(&cfg)?)?;
        let training = file.metadata.get("training").cloned().unwrap_or_default();
        Self::from_tensors(&cfg, tensors, training)
    }

    /// An estimator from named tensors (as in a weights file).
    pub fn from_tensors(
        cfg: &Config,
        tensors: Vec<(String, Tensor)>,
        training: String,
    ) -> Result<Self> {
        let map: HashMap<String, Tensor> = tensors.iter().cloned().collect();
        let net = EmotionNet::new(cfg, VarBuilder::from_tensors(map, DType::F32, &Device::Cpu))?;
        Ok(Self {
            net,
            tensors,
            training,
        })
    }

    /// Writes the weights file (through a temporary file).
    pub fn save(&self, path: &Path) -> Result<()> {
        Ok(file::write_atomically(path, &self.to_bytes()?)?)
    }

    /// The weights file's bytes.
    pub fn to_bytes(&self) -> Result<Vec<u8>> {
        let meta = file::metadata(
            FORMAT_NAME,
            FORMAT_VERSION,
            &[
                ("config", file::to_json(self.net.config())?),
                ("training", self.training.clone()),
            ],
        );
        Ok(file::encode(&self.tensors, meta)?)
    }

    /// The network.
    pub fn net(&self) -> &EmotionNet {
        &self.net
    }

    /// How the weights were trained (JSON written by the trainer; may be empty).
    pub fn training_info(&self) -> &str {
        &self.training
    }

    /// Replaces the training description.
    pub fn set_training_info(&mut self, info: String) {
        self.training = info;
    }

    /// Arousal per frame (2 Hz, clamped to [-1, 1]) of a `(frames, 64)` mel dB spectrogram.
    pub fn predict(&self, mel_db: ArrayView2<f32>) -> Result<Vec<f32>> {
        predict_with(&self.net, mel_db)
    }

    /// Arousal at 2 Hz of a recording.
    pub fn predict_audio(&self, audio: &dsp_mel::Audio) -> Result<Vec<f32>> {
        self.predict(emotion_mel(audio)?.view())
    }
}

/// Frames between the starts of consecutive inference windows (windows overlap by half).
pub const INFER_HOP_STEPS: usize = 10;

/// Overlap-averaged arousal of a whole spectrogram with `net` (inference mode), after the
/// level normalisation of the network's configuration (`Config::gain_norm`): `steps`-frame
/// windows every [`INFER_HOP_STEPS`] frames, the last one aligned with the end, averaged
/// where they overlap; a recording shorter than one window is padded with its quietest value
/// and the output cut back.
pub fn predict_with(net: &EmotionNet, mel_db: ArrayView2<f32>) -> Result<Vec<f32>> {
    predict_with_hop(net, mel_db, INFER_HOP_STEPS)
}

/// [`predict_with`] with windows every `hop` frames (1 = every frame).
pub fn predict_with_hop(net: &EmotionNet, mel_db: ArrayView2<f32>, hop: usize) -> Result<Vec<f32>> {
    let cfg = net.config();
    check_mel(mel_db, cfg.n_mels)?;
    let normalised = cfg.gain_norm.apply(mel_db);
    let mel_db = normalised.view();
    let frames = mel_db.nrows();
    let t = cfg.steps;
    let pad = mel_db.iter().copied().fold(f32::INFINITY, f32::min);
    let padded = frames.max(t);
    let last = padded - t;
    let mut starts: Vec<usize> = (0..=last).step_by(hop.max(1)).collect();
    if starts.last() != Some(&last) {
        starts.push(last);
    }
    let bands = cfg.n_mels;
    let mut buf = vec![0.0f32; starts.len() * t * bands];
    for (&s, chunk) in starts.iter().zip(buf.chunks_exact_mut(t * bands)) {
        net_core::frames::copy_frames(mel_db, s as isize, t, pad, chunk);
    }
    let x = Tensor::from_vec(buf, (starts.len(), t, bands), &Device::Cpu)?;
    let y = net.forward_t(&x, false)?.to_vec2::<f32>()?;
    let mut sum = vec![0.0f32; padded];
    let mut count = vec![0u32; padded];
    for (&s, row) in starts.iter().zip(&y) {
        for (k, v) in row.iter().enumerate() {
            sum[s + k] += v;
            count[s + k] += 1;
        }
    }
    Ok(sum
        .iter()
        .zip(&count)
        .take(frames)
        .map(|(s, &c)| (s / c.max(1) as f32).clamp(-1.0, 1.0))
        .collect())
}

/// Pearson correlation of two equally long series (0 when either is constant).
///
/// ```
/// let r = emotion_net::estimator::pearson(&[1.0, 2.0, 3.0], &[2.0, 4.0, 6.5]);
/// assert!(r > 0.99);
/// ```
pub fn pearson(a: &[f32], b: &[f32]) -> f64 {
    let n = a.len().min(b.len());
    if n < 2 {
        return 0.0;
    }
    let ma = a[..n].iter().map(|&v| f64::from(v)).sum::<f64>() / n as f64;
    let mb = b[..n].iter().map(|&v| f64::from(v)).sum::<f64>() / n as f64;
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (&x, &y) in a[..n].iter().zip(&b[..n]) {
        let (dx, dy) = (f64::from(x) - ma, f64::from(y) - mb);
        sab += dx * dy;
        saa += dx * dx;
        sbb += dy * dy;
    }
    if saa == 0.0 || sbb == 0.0 {
        0.0
    } else {
        sab / (saa * sbb).sqrt()
    }
}
