//! Training progress that survives a restart: early stopping on a validation metric, the
//! per-epoch losses, and checkpoint files (model tensors + Adam moments + this state) written
//! beside the output weights so that `--resume` continues exactly where training stopped.

use std::path::{Path, PathBuf};

use candle_core::Tensor;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::adam::Adam;
use crate::error::{Result, StoreError};
use crate::file::{self, TensorFile};
use crate::vars;

/// The checkpoint written beside `out`: `W.safetensors` → `W.ckpt.safetensors`.
///
/// ```
/// let p = net_core::checkpoint_path("runs/bowing.safetensors".as_ref());
/// assert_eq!(p, std::path::PathBuf::from("runs/bowing.ckpt.safetensors"));
/// ```
pub fn checkpoint_path(out: &Path) -> PathBuf {
    out.with_extension("ckpt.safetensors")
}

/// Where training stands: the next epoch, the best validation metric (higher is better) and
/// when it was reached, and the losses so far; `model` is the network's configuration, so a
/// checkpoint of another shape is refused.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainState<C> {
    /// The first epoch still to run.
    pub next_epoch: usize,
    /// Best validation metric so far (the start value when none yet).
    #[serde(alias = "best_f1", alias = "best_r")]
    pub best_metric: f64,
    /// Epoch (0-based) of the best metric.
    pub best_epoch: usize,
    /// Epochs since the best metric.
    pub since_best: usize,
    /// Mean training loss per epoch.
    pub epoch_losses: Vec<f32>,
    /// The network's configuration.
    pub model: C,
}

impl<C> TrainState<C> {
    /// A fresh state; `worst` is below any metric value (e.g. −1 for F1, −2 for Pearson r).
    pub fn new(model: C, worst: f64) -> Self {
        Self {
            next_epoch: 0,
            best_metric: worst,
            best_epoch: 0,
            since_best: 0,
            epoch_losses: Vec::new(),
            model,
        }
    }

    /// Records the end of epoch `epoch` with its mean loss and validation metric; returns
    /// whether the metric is a new best (then the caller keeps these weights).
    ///
    /// ```
    /// let mut s = net_core::TrainState::new((), -1.0);
    /// assert!(s.end_epoch(0, 0.5, 0.7));
    /// assert!(!s.end_epoch(1, 0.4, 0.6));
    /// assert_eq!((s.best_epoch, s.since_best, s.next_epoch), (0, 1, 2));
    /// assert!(s.should_stop(1) && !s.should_stop(2));
    /// ```
    pub fn end_epoch(&mut self, epoch: usize, loss: f32, metric: f64) -> bool {
        self.epoch_losses.push(loss);
        self.next_epoch = epoch + 1;
        if metric > self.best_metric {
            self.best_metric = metric;
            self.best_epoch = epoch;
            self.since_best = 0;
            true
        } else {
            self.since_best += 1;
            false
        }
    }

    /// Whether `patience` epochs have passed without a better metric.
    pub fn should_stop(&self, patience: usize) -> bool {
        self.since_best >= patience
    }
}

/// Metadata key of the checkpoint's [`TrainState`] (JSON).
pub const KEY_STATE: &str = "state";

/// Writes a checkpoint (through a temporary file): `tensors` (the model's), Adam's moments
/// and step, and `state`, under the format name `format` and `version`.
pub fn save_checkpoint<S: Serialize>(
    path: &Path,
    format: &str,
    version: u32,
    mut tensors: Vec<(String, Tensor)>,
    adam: &Adam,
    state: &S,
) -> Result<()> {
    tensors.extend(adam.state()?);
    let meta = file::metadata(format, version, &[(KEY_STATE, file::to_json(state)?)]);
    file::write_atomically(path, &file::encode(&tensors, meta)?)
}

/// Reads a checkpoint written by [`save_checkpoint`]: checks its format name and version and
/// returns its tensors and state. A missing file is an error naming it.
pub fn load_checkpoint<S: DeserializeOwned>(
    path: &Path,
    format: &str,
    version: u32,
) -> Result<(TensorFile, S)> {
    if !path.is_file() {
        return Err(StoreError::io(
            path,
            "no checkpoint to resume from: train without --resume first",
        ));
    }
    let file = file::read(path)?;
    file.check_format(path, format, version)?;
    let state = file.meta_json(KEY_STATE, path)?;
    Ok((file, state))
}

/// Continues a training run: reads the checkpoint at `path` ([`load_checkpoint`]), refuses it
/// when its network configuration is not `model`, and loads its tensors into `varmap` and its
/// moments into `adam`; returns where training stands.
pub fn resume_from_checkpoint<C: DeserializeOwned + PartialEq>(
    path: &Path,
    format: &str,
    version: u32,
    model: &C,
    varmap: &candle_nn::VarMap,
    adam: &mut Adam,
) -> Result<TrainState<C>> {
    let (file, state): (_, TrainState<C>) = load_checkpoint(path, format, version)?;
    if &state.model != model {
        return Err(StoreError::weights(
            path,
            "the checkpoint's network shape differs from the requested one",
        ));
    }
    vars::load_into(varmap, &file.tensors, path)?;
    adam.load_state(&file.tensors)?;
    Ok(state)
}
