//! Training checkpoints (`W.ckpt.safetensors` beside the weights `W.safetensors`): the
//! latest parameters and Adam moments (f32), with the configuration, normalisation and
//! progress in the metadata, so `--resume` continues where training stopped.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use candle_core::{Device, Tensor};
use serde::{Deserialize, Serialize};

use super::adam::Adam;
use super::{EpochReport, TrainConfig};
use crate::config::Config;
use crate::error::{GruError, Result};
use crate::model::GruBaseline;
use crate::norm::{MelStats, TargetSpace};
use crate::weights::write_atomically;

const CHECKPOINT_FORMAT: &str = "gru-baseline-checkpoint";
const CHECKPOINT_VERSION: u32 = 1;

/// Where the checkpoint of weights file `out` goes: `W.safetensors` → `W.ckpt.safetensors`.
///
/// ```
/// use std::path::Path;
/// assert_eq!(gru_baseline::train::checkpoint_path(Path::new("a/w.safetensors")), Path::new("a/w.ckpt.safetensors"));
/// ```
pub fn checkpoint_path(out: &Path) -> PathBuf {
    out.with_extension("ckpt.safetensors")
}

/// Progress saved with a checkpoint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Progress {
    /// Epochs completed.
    pub epochs_done: usize,
    /// Adam updates taken.
    pub adam_steps: u64,
    /// Current learning rate.
    pub learning_rate: f64,
    /// Best selection loss so far (validation, or training without a validation set).
    pub best_loss: f64,
    /// Epoch of the best loss (0 = none yet).
    pub best_epoch: usize,
    /// Epochs since the best one.
    pub epochs_since_best: usize,
    /// Training wall time so far, seconds.
    pub wall_time_s: f64,
    /// One report per completed epoch.
    pub history: Vec<EpochReport>,
}

/// A loaded checkpoint.
#[derive(Debug)]
pub(crate) struct Checkpoint {
    pub config: Config,
    pub train: TrainConfig,
    pub mel_stats: MelStats,
    pub target: TargetSpace,
    pub progress: Progress,
    pub tensors: HashMap<String, Tensor>,
}

fn err(path: &Path, reason: impl Into<String>) -> GruError {
    GruError::Weights {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}

fn json<T: Serialize>(v: &T) -> Result<String> {
    serde_json::to_string(v)
        .map_err(|e| GruError::Config(format!("cannot serialise checkpoint metadata ({e})")))
}

/// Writes the checkpoint atomically.
pub(crate) fn save(
    path: &Path,
    net: &GruBaseline,
    adam: &Adam,
    train: &TrainConfig,
    progress: &Progress,
) -> Result<()> {
    let mut meta = HashMap::new();
    meta.insert("format".to_string(), CHECKPOINT_FORMAT.to_string());
    meta.insert("version".to_string(), CHECKPOINT_VERSION.to_string());
    meta.insert("config".to_string(), json(net.config())?);
    meta.insert("train".to_string(), json(train)?);
    meta.insert("mel_stats".to_string(), json(net.mel_stats())?);
    meta.insert("target_space".to_string(), json(net.target_space())?);
    meta.insert("progress".to_string(), json(progress)?);
    let mut tensors: Vec<(String, Tensor)> = net
        .named_parameters()
        .into_iter()
        .map(|(n, t)| (format!("param.{n}"), t.detach()))
        .collect();
    let (moments, _) = adam.state();
    tensors.extend(moments.into_iter().map(|(n, t)| (format!("adam.{n}"), t)));
    tensors.sort_by(|a, b| a.0.cmp(&b.0));
    let bytes = safetensors::serialize(tensors.iter().map(|(n, t)| (n.as_str(), t)), Some(meta))
        .map_err(|e| GruError::Config(format!("cannot serialise the checkpoint ({e})")))?;
    write_atomically(path, &bytes)
}

fn field<T: serde::de::DeserializeOwned>(
    meta: &HashMap<String, String>,
    key: &str,
    path: &Path,
) -> Result<T> {
    let text = meta
        .get(key)
        .ok_or_else(|| err(path, format!("checkpoint metadata lacks `{key}`")))?;
    serde_json::from_str(text).map_err(|e| {
        err(
            path,
            format!("checkpoint metadata `{key}` is unreadable ({e})"),
        )
    })
}

/// Reads a checkpoint written by [`save`].
pub(crate) fn load(path: &Path) -> Result<Checkpoint> {
    let bytes = std::fs::read(path).map_err(|e| {
        err(
            path,
            format!("cannot read the checkpoint ({e}); --resume needs the .ckpt.safetensors of an earlier run with the same --out"),
        )
    })?;
    let (_, header) = safetensors::SafeTensors::read_metadata(&bytes)
        .map_err(|e| err(path, format!("not a safetensors file ({e})")))?;
    let empty = HashMap::new();
    let meta = header.metadata().as_ref().unwrap_or(&empty);
    if meta.get("format").map(String::as_str) != Some(CHECKPOINT_FORMAT) {
        return Err(err(path, "not a gru-baseline training checkpoint"));
    }
    let version: u32 = field(meta, "version", path)?;
    if version != CHECKPOINT_VERSION {
        return Err(err(
            path,
            format!(
                "checkpoint version {version}, expected {CHECKPOINT_VERSION}; start a new training"
            ),
        ));
    }
    let tensors = candle_core::safetensors::load_buffer(&bytes, &Device::Cpu).map_err(|e| {
        err(
            path,
            format!("cannot read the tensors ({e}); the file may be truncated"),
        )
    })?;
    Ok(Checkpoint {
        config: field(meta, "config", path)?,
        train: field(meta, "train", path)?,
        mel_stats: field(meta, "mel_stats", path)?,
        target: field(meta, "target_space", path)?,
        progress: field(meta, "progress", path)?,
        tensors,
    })
}
