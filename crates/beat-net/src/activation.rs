//! A trained beat network as stored in a weights file, and its per-frame activations; the
//! shipped default is embedded in the crate.
//!
//! A file may hold one network (format version 1) or an ensemble of networks of one shape
//! trained with different seeds (version 2: tensors prefixed `member{i}/`, metadata
//! `members`), whose per-frame probabilities are averaged.

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
/// Weights format version of a file holding one network (bump when names, shapes or
/// meaning change).
pub const FORMAT_VERSION: u32 = 1;
/// Weights format version of a file holding an ensemble ([`BeatActivation::ensemble`]).
pub const ENSEMBLE_FORMAT_VERSION: u32 = 2;
/// Metadata key of an ensemble file: how many members it holds.
const KEY_MEMBERS: &str = "members";
/// Most members an ensemble file may declare (each costs one network pass).
pub const MAX_MEMBERS: usize = 16;

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

/// One network (or several of one shape, averaged) with its input normalisation (module
/// docs).
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
    members: Vec<Member>,
    training: String,
}

/// One network of a [`BeatActivation`] and the tensors it was built from.
#[derive(Debug)]
struct Member {
    net: BeatNet,
    tensors: Vec<(String, Tensor)>,
}

impl Member {
    fn new(cfg: &Config, tensors: Vec<(String, Tensor)>) -> Result<Self> {
        let map: HashMap<String, Tensor> = tensors.iter().cloned().collect();
        let net = BeatNet::new(cfg, VarBuilder::from_tensors(map, DTYPE, &Device::Cpu))?;
        Ok(Self { net, tensors })
    }
}

/// The tensor-name prefix of ensemble member `i`.
fn member_prefix(i: usize) -> String {
    format!("member{i}/")
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
        let ensemble = file
            .check_format(path, FORMAT_NAME, ENSEMBLE_FORMAT_VERSION)
            .is_ok();
        if !ensemble {
            file.check_format(path, FORMAT_NAME, FORMAT_VERSION)?;
        }
        let cfg: Config = file.meta_json("config", path)?;
        cfg.validate().map_err(|e| BeatNetError::weights(path, e))?;
        let training = file.metadata.get("training").cloned().unwrap_or_default();
        let shapes = expected_shapes(&cfg)?;
        if !ensemble {
            let tensors = file.take_expected(path, &shapes)?;
            return Self::from_tensors(&cfg, tensors, training);
        }
        let count: usize = file.meta_json(KEY_MEMBERS, path)?;
        if !(1..=MAX_MEMBERS).contains(&count) {
            return Err(BeatNetError::weights(
                path,
                format!("it declares {count} ensemble members, 1 to {MAX_MEMBERS} are readable"),
            ));
        }
        let mut members = Vec::with_capacity(count);
        for i in 0..count {
            let prefix = member_prefix(i);
            let prefixed: Vec<(String, Vec<usize>)> = shapes
                .iter()
                .map(|(n, s)| (format!("{prefix}{n}"), s.clone()))
                .collect();
            let tensors = file
                .take_expected(path, &prefixed)?
                .into_iter()
                .map(|(n, t)| (n[prefix.len()..].to_string(), t))
                .collect();
            members.push(Member::new(&cfg, tensors)?);
        }
        Ok(Self { members, training })
    }

    /// The networks of `parts` (each one network or an ensemble) as one ensemble whose
    /// activations are the mean of theirs; all must have the same [`Config`].
    ///
    /// ```no_run
    /// use beat_net::BeatActivation;
    /// let a = BeatActivation::load("seed1.safetensors".as_ref())?;
    /// let b = BeatActivation::load("seed2.safetensors".as_ref())?;
    /// BeatActivation::ensemble(vec![a, b])?.save("ensemble.safetensors".as_ref())?;
    /// # Ok::<(), beat_net::BeatNetError>(())
    /// ```
    pub fn ensemble(parts: Vec<BeatActivation>) -> Result<Self> {
        let Some(first) = parts.first() else {
            return Err(BeatNetError::Config(
                "an ensemble needs at least one network".into(),
            ));
        };
        let cfg = first.net().config().clone();
        if let Some(other) = parts.iter().find(|p| p.net().config() != &cfg) {
            return Err(BeatNetError::Config(format!(
                "ensemble members must share one shape: {:?} and {:?} differ",
                cfg,
                other.net().config()
            )));
        }
        let training: Vec<serde_json::Value> = parts
            .iter()
            .map(|p| {
                serde_json::from_str(&p.training)
                    .unwrap_or_else(|_| serde_json::Value::String(p.training.clone()))
            })
            .collect();
        let members: Vec<Member> = parts.into_iter().flat_map(|p| p.members).collect();
        if members.len() > MAX_MEMBERS {
            return Err(BeatNetError::Config(format!(
                "{} networks, an ensemble holds at most {MAX_MEMBERS}",
                members.len()
            )));
        }
        let training = serde_json::json!({ "ensemble_of": training }).to_string();
        Ok(Self { members, training })
    }

    /// How many networks are averaged (1 for a single network).
    pub fn member_count(&self) -> usize {
        self.members.len()
    }

    /// A network from named tensors (as in a weights file).
    pub fn from_tensors(
        cfg: &Config,
        tensors: Vec<(String, Tensor)>,
        training: String,
    ) -> Result<Self> {
        Ok(Self {
            members: vec![Member::new(cfg, tensors)?],
            training,
        })
    }

    /// A copy of the variables of `varmap` (e.g. during training).
    pub fn from_varmap(cfg: &Config, varmap: &VarMap, training: String) -> Result<Self> {
        let tensors = vars::var_tensors(varmap)
            .into_iter()
            .map(|(n, t)| t.copy().map(|t| (n, t)))
            .collect::<candle_core::Result<Vec<_>>>()?;
        Self::from_tensors(cfg, tensors, training)
    }

    /// Writes the weights file (through a temporary file).
    pub fn save(&self, path: &Path) -> Result<()> {
        Ok(file::write_atomically(path, &self.to_bytes()?)?)
    }

    /// The weights file's bytes (format version 1 for one network, 2 for an ensemble).
    pub fn to_bytes(&self) -> Result<Vec<u8>> {
        let config = ("config", file::to_json(self.net().config())?);
        let training = ("training", self.training.clone());
        if let [only] = self.members.as_slice() {
            let meta = file::metadata(FORMAT_NAME, FORMAT_VERSION, &[config, training]);
            return Ok(file::encode(&only.tensors, meta)?);
        }
        let count = (KEY_MEMBERS, self.members.len().to_string());
        let meta = file::metadata(
            FORMAT_NAME,
            ENSEMBLE_FORMAT_VERSION,
            &[config, training, count],
        );
        let tensors: Vec<(String, Tensor)> = self
            .members
            .iter()
            .enumerate()
            .flat_map(|(i, m)| {
                let prefix = member_prefix(i);
                m.tensors
                    .iter()
                    .map(move |(n, t)| (format!("{prefix}{n}"), t.clone()))
            })
            .collect();
        Ok(file::encode(&tensors, meta)?)
    }

    /// The network (the first member of an ensemble).
    pub fn net(&self) -> &BeatNet {
        &self.members[0].net
    }

    /// How the weights were trained (JSON written by the trainer; may be empty).
    pub fn training_info(&self) -> &str {
        &self.training
    }

    /// Activations of a `(frames, 128)` mel dB spectrogram at 30 fps (no frames → none);
    /// an ensemble's are the mean of its members'.
    pub fn activations(&self, mel_db: ArrayView2<f32>) -> Result<Activations> {
        if mel_db.nrows() == 0 {
            return Ok(Activations::default());
        }
        let n_mels = self.net().config().n_mels;
        net_core::frames::check_mel(mel_db, n_mels)?;
        let x = frame_features(mel_db)?;
        let frames = x.nrows();
        let mut out = Activations {
            beat: vec![0.0; frames],
            downbeat: vec![0.0; frames],
        };
        let weight = 1.0 / self.members.len() as f32;
        for member in &self.members {
            let logits = member.net.frame_logits(x.view())?;
            let mut p = vec![0.0f32; logits.ncols()];
            for ((row, beat), downbeat) in logits
                .rows()
                .into_iter()
                .zip(&mut out.beat)
                .zip(&mut out.downbeat)
            {
                p.iter_mut().zip(row).for_each(|(d, v)| *d = *v);
                softmax_in_place(&mut p);
                *beat += weight * p.get(1).copied().unwrap_or(f32::NAN);
                *downbeat += weight * p.get(2).copied().unwrap_or(f32::NAN);
            }
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
