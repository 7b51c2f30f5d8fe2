//! A trained beat network as stored in a weights file, and its per-frame activations; the
//! shipped default is embedded in the crate.

use std::collections::HashMap;
use std::path::Path;

use candle_core::{Device, Tensor, D};
use candle_nn::{VarBuilder, VarMap};
use ndarray::ArrayView2;
use net_core::file::{self, TensorFile};
use net_core::nn::softmax_in_place;
use net_core::vars;

use crate::error::{BeatNetError, Result};
use crate::features::frame_features;
use crate::model::{BeatNet, Config, DTYPE};

/// Value of the `format` metadata entry of beat-net weights.
pub const FORMAT_NAME: &str = "violin-skeleton/beat-net";
/// Current weights format version (bump when names, shapes or meaning change).
pub const FORMAT_VERSION: u32 = 1;

/// The shipped default weights (see the crate README for how they were trained).
static PRETRAINED: &[u8] = include_bytes!("../weights/beat-net.safetensors");

/// Per-frame (30 fps) probabilities, as madmom's `RNNDownBeatProcessor`: `beat` is a beat
/// that is not a downbeat, `downbeat` a downbeat; `1 − beat − downbeat` is no beat.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Activations {
    /// P(beat, not a downbeat) per frame.
    pub beat: Vec<f32>,
    /// P(downbeat) per frame.
    pub downbeat: Vec<f32>,
}

impl Activations {
    /// Frames.
    pub fn len(&self) -> usize {
        self.beat.len()
    }

    /// Whether there are no frames.
    pub fn is_empty(&self) -> bool {
        self.beat.is_empty()
    }

    /// P(any beat) per frame (`beat + downbeat`).
    pub fn any_beat(&self) -> Vec<f32> {
        self.beat
            .iter()
            .zip(&self.downbeat)
            .map(|(b, d)| b + d)
            .collect()
    }
}

/// The network with its input normalisation (module docs).
///
/// ```no_run
/// let net = beat_net::BeatActivation::pretrained()?;
/// let mel = ndarray::Array2::<f32>::from_elem((300, 128), -60.0);
/// let act = net.activations(mel.view())?;
/// assert_eq!(act.len(), 300);
/// # Ok::<(), beat_net::BeatNetError>(())
/// ```
#[derive(Debug)]
pub struct BeatActivation {
    net: BeatNet,
    tensors: Vec<(String, Tensor)>,
    training: String,
}

/// The variable names and shapes a network of `cfg` has.
pub fn expected_shapes(cfg: &Config) -> Result<Vec<(String, Vec<usize>)>> {
    let varmap = VarMap::new();
    BeatNet::new(cfg, VarBuilder::from_varmap(&varmap, DTYPE, &Device::Cpu))?;
    Ok(vars::var_shapes(&varmap))
}

impl BeatActivation {
    /// The embedded default weights.
    pub fn pretrained() -> Result<Self> {
        Self::from_bytes(PRETRAINED, Path::new("<embedded beat-net weights>"))
    }

    /// Reads weights written by [`BeatActivation::save`]; rejects other networks, other
    /// format versions and tensors whose shapes do not match the stored configuration.
    pub fn load(path: &Path) -> Result<Self> {
        Self::from_file(file::read(path)?, path)
    }

    /// [`BeatActivation::load`] from bytes; `path` names them in errors.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self> {
        Self::from_file(file::decode(bytes, path)?, path)
    }

    fn from_file(file: TensorFile, path: &Path) -> Result<Self> {
        file.check_format(path, FORMAT_NAME, FORMAT_VERSION)?;
        let cfg: Config = file.meta_json("config", path)?;
        cfg.validate().map_err(|e| BeatNetError::weights(path, e))?;
        let tensors = file.take_expected(path, &expected_shapes(&cfg)?)?;
        let training = file.metadata.get("training").cloned().unwrap_or_default();
        Self::from_tensors(&cfg, tensors, training)
    }

    /// A network from named tensors (as in a weights file).
    pub fn from_tensors(
        cfg: &Config,
        tensors: Vec<(String, Tensor)>,
        training: String,
    ) -> Result<Self> {
        let map: HashMap<String, Tensor> = tensors.iter().cloned().collect();
        let net = BeatNet::new(cfg, VarBuilder::from_tensors(map, DTYPE, &Device::Cpu))?;
        Ok(Self {
            net,
            tensors,
            training,
        })
    }

    /// A copy of the variables of `varmap` (e.g. during training).
    pub fn from_varmap(cfg: &Config, varmap: &VarMap, training: String) -> Result<Self> {
        let tensors = vars::copied_tensors(varmap)?;
        Self::from_tensors(cfg, tensors, training)
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
    pub fn net(&self) -> &BeatNet {
        &self.net
    }

    /// How the weights were trained (JSON written by the trainer; may be empty).
    pub fn training_info(&self) -> &str {
        &self.training
    }

    /// Activations of a `(frames, 128)` mel dB spectrogram at 30 fps (no frames → none).
    pub fn activations(&self, mel_db: ArrayView2<f32>) -> Result<Activations> {
        if mel_db.nrows() == 0 {
            return Ok(Activations::default());
        }
        let n_mels = self.net.config().n_mels;
        net_core::frames::check_mel(mel_db, n_mels)?;
        let x = frame_features(mel_db)?;
        let logits = self.net.frame_logits(x.view())?;
        let mut out = Activations::default();
        let mut p = vec![0.0f32; logits.ncols()];
        for row in logits.rows() {
            p.iter_mut().zip(row).for_each(|(d, v)| *d = *v);
            softmax_in_place(&mut p);
            out.beat.push(p.get(1).copied().unwrap_or(f32::NAN));
            out.downbeat.push(p.get(2).copied().unwrap_or(f32::NAN));
        }
        Ok(out)
    }
}

/// Softmax of `(1, frames, 3)` logits → [`Activations`].
pub fn probabilities(logits: &Tensor) -> Result<Activations> {
    let p = candle_nn::ops::softmax(&logits.squeeze(0)?, D::Minus1)?.to_vec2::<f32>()?;
    Ok(Activations {
        beat: p.iter().map(|r| r[1]).collect(),
        downbeat: p.iter().map(|r| r[2]).collect(),
    })
}
