//! A trained bowing network with its decoder, as stored in a weights file; the shipped
//! default is embedded in the crate.

use std::collections::HashMap;
use std::path::Path;

use candle_core::{Device, Tensor};
use candle_nn::{VarBuilder, VarMap};
use ndarray::ArrayView2;

use crate::decode::Decoder;
use crate::error::{NetError, Result};
use crate::features::{bowing_mel, FPS};
use crate::infer::frame_probabilities;
use crate::model::{BowingNet, Config, DTYPE};
use net_core::file::{self, TensorFile};
use net_core::vars;

/// Value of the `format` metadata entry of bowing-net weights.
pub const FORMAT_NAME: &str = "violin-skeleton/bowing-net";
/// Current weights format version (bump when names, shapes or meaning change).
pub const FORMAT_VERSION: u32 = 1;

/// The shipped default weights (see the crate README for how they were trained).
static PRETRAINED: &[u8] = include_bytes!("../weights/bowing-net.safetensors");

/// Bow-change detection: the network, its input normalisation and its decoder.
///
/// ```no_run
/// let detector = bowing_net::BowChangeDetector::pretrained()?;
/// let audio = dsp_mel::load_audio("take1.wav")?;
/// let changes_s = detector.detect_audio(&audio)?;
/// println!("{} bow changes", changes_s.len());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct BowChangeDetector {
    net: BowingNet,
    decoder: Decoder,
    tensors: Vec<(String, Tensor)>,
    training: String,
}

/// The variable names and shapes a network of `cfg` has.
pub fn expected_shapes(cfg: &Config) -> Result<Vec<(String, Vec<usize>)>> {
    let varmap = VarMap::new();
    BowingNet::new(cfg, VarBuilder::from_varmap(&varmap, DTYPE, &Device::Cpu))?;
    Ok(vars::var_shapes(&varmap))
}

impl BowChangeDetector {
    /// The embedded default weights.
    pub fn pretrained() -> Result<Self> {
        Self::from_bytes(PRETRAINED, Path::new("<embedded bowing-net weights>"))
    }

    /// Reads weights written by [`BowChangeDetector::save`] (e.g. by
    /// `violin-skeleton train bowing`); rejects other networks, other format versions and
    /// tensors whose shapes do not match the stored configuration.
    pub fn load(path: &Path) -> Result<Self> {
        Self::from_file(file::read(path)?, path)
    }

    /// [`BowChangeDetector::load`] from bytes; `path` names them in errors.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self> {
        Self::from_file(file::decode(bytes, path)?, path)
    }

    fn from_file(file: TensorFile, path: &Path) -> Result<Self> {
        file.check_format(path, FORMAT_NAME, FORMAT_VERSION)?;
        let cfg: Config = file.meta_json("config", path)?;
        cfg.validate().map_err(|e| NetError::weights(path, e))?;
        let decoder: Decoder = file.meta_json("decoder", path)?;
        let tensors = file.take_expected(path, &expected_shapes(&cfg)?)?;
        let training = file.metadata.get("training").cloned().unwrap_or_default();
        Self::from_tensors(&cfg, tensors, decoder, training)
    }

    /// A detector from named tensors (as in a weights file).
    pub fn from_tensors(
        cfg: &Config,
        tensors: Vec<(String, Tensor)>,
        decoder: Decoder,
        training: String,
    ) -> Result<Self> {
        let map: HashMap<String, Tensor> = tensors.iter().cloned().collect();
        let net = BowingNet::new(cfg, VarBuilder::from_tensors(map, DTYPE, &Device::Cpu))?;
        Ok(Self {
            net,
            decoder,
            tensors,
            training,
        })
    }

    /// A detector holding a copy of the variables of `varmap` (e.g. during training).
    pub fn from_varmap(
        cfg: &Config,
        varmap: &VarMap,
        decoder: Decoder,
        training: String,
    ) -> Result<Self> {
        let tensors = vars::copied_tensors(varmap)?;
        Self::from_tensors(cfg, tensors, decoder, training)
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
                ("decoder", file::to_json(&self.decoder)?),
                ("training", self.training.clone()),
            ],
        );
        Ok(file::encode(&self.tensors, meta)?)
    }

    /// The network.
    pub fn net(&self) -> &BowingNet {
        &self.net
    }

    /// The decoder (threshold and minimum spacing tuned on validation data at training).
    pub fn decoder(&self) -> Decoder {
        self.decoder
    }

    /// Replaces the decoder.
    pub fn set_decoder(&mut self, decoder: Decoder) {
        self.decoder = decoder;
    }

    /// Replaces the training description stored with the weights.
    pub fn set_training_info(&mut self, info: String) {
        self.training = info;
    }

    /// How the weights were trained (JSON written by the trainer; may be empty).
    pub fn training_info(&self) -> &str {
        &self.training
    }

    /// Per-frame change probabilities of a `(frames, 128)` mel dB spectrogram at 30 fps.
    pub fn frame_probabilities(&self, mel_db: ArrayView2<f32>) -> Result<Vec<f32>> {
        frame_probabilities(&self.net, mel_db)
    }

    /// Bow-change frames (30 fps) of a mel dB spectrogram.
    pub fn detect_frames(&self, mel_db: ArrayView2<f32>) -> Result<Vec<usize>> {
        Ok(self.decoder.pick(&self.frame_probabilities(mel_db)?))
    }

    /// Bow-change times in seconds of a recording, between frames where the probabilities
    /// say so ([`Decoder::pick_fractional`]).
    pub fn detect_audio(&self, audio: &dsp_mel::Audio) -> Result<Vec<f64>> {
        let mel = bowing_mel(audio)?;
        let probs = self.frame_probabilities(mel.view())?;
        Ok(self
            .decoder
            .pick_fractional(&probs)
            .into_iter()
            .map(|f| f / FPS)
            .collect())
    }
}
