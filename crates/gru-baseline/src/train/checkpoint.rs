//! Training checkpoints (`W.ckpt.safetensors` beside the weights `W.safetensors`), written
//! and read by `net-core`: the latest parameters (`param.NAME`) and Adam moments, with the
//! configuration, normalisation and progress as the checkpoint's state, so `--resume`
//! continues where training stopped.

use std::collections::HashMap;
use std::path::Path;

use candle_core::Tensor;
use net_core::Adam;
use serde::{Deserialize, Serialize};

use super::settings::{EpochReport, TrainConfig};
use crate::config::Config;
use crate::error::Result;
use crate::model::GruBaseline;
use crate::norm::{MelStats, TargetSpace};

pub use net_core::checkpoint_path;

const CHECKPOINT_FORMAT: &str = "gru-baseline-checkpoint";
/// Version 2: net-core's checkpoint layout (state JSON, `adam.step` tensor).
const CHECKPOINT_VERSION: u32 = 2;

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

/// Everything but the tensors: the checkpoint's state.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct State {
    config: Config,
    train: TrainConfig,
    mel_stats: MelStats,
    target_space: TargetSpace,
    progress: Progress,
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

/// Writes the checkpoint atomically.
pub(crate) fn save(
    path: &Path,
    net: &GruBaseline,
    adam: &Adam,
    train: &TrainConfig,
    progress: &Progress,
) -> Result<()> {
    let mut tensors: Vec<(String, Tensor)> = net
        .named_parameters()
        .into_iter()
        .map(|(n, t)| (format!("param.{n}"), t.detach()))
        .collect();
    tensors.sort_by(|a, b| a.0.cmp(&b.0));
    let state = State {
        config: net.config().clone(),
        train: train.clone(),
        mel_stats: net.mel_stats().clone(),
        target_space: net.target_space().clone(),
        progress: progress.clone(),
    };
    net_core::save_checkpoint(
        path,
        CHECKPOINT_FORMAT,
        CHECKPOINT_VERSION,
        tensors,
        adam,
        &state,
    )?;
    Ok(())
}

/// Reads a checkpoint written by [`save`].
pub(crate) fn load(path: &Path) -> Result<Checkpoint> {
    let (file, state): (_, State) =
        net_core::load_checkpoint(path, CHECKPOINT_FORMAT, CHECKPOINT_VERSION)?;
    Ok(Checkpoint {
        config: state.config,
        train: state.train,
        mel_stats: state.mel_stats,
        target: state.target_space,
        progress: state.progress,
        tensors: file.tensors,
    })
}
