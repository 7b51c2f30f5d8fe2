//! The settings of a training run and the report of one epoch (what checkpoints store).

use serde::{Deserialize, Serialize};

use crate::error::{GruError, Result};
use crate::loss::Loss;

/// Settings of a training run; the default trains the shipped weights.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainConfig {
    /// Epochs (passes over the training sequences), counting those of a resumed run.
    pub epochs: usize,
    /// Parallel streams (batch rows).
    pub batch_size: usize,
    /// Frames per truncated-BPTT window (5 s at 150).
    pub window_frames: usize,
    /// Adam's initial learning rate.
    pub learning_rate: f64,
    /// Global gradient-norm clip.
    pub clip_grad_norm: f64,
    /// Halve the learning rate after this many epochs without a better validation loss.
    pub lr_patience: usize,
    /// Stop after this many epochs without a better validation loss (0 = never).
    pub early_stop_patience: usize,
    /// The loss (MSE or right-arm weighted).
    pub loss: Loss,
    /// Seed of initialisation, shuffling, window phases and dropout.
    pub seed: u64,
    /// Cap on updates per epoch (tests and quick trials); `None` = whole epochs.
    pub max_steps_per_epoch: Option<usize>,
}

impl Default for TrainConfig {
    fn default() -> Self {
        Self {
            epochs: 30,
            batch_size: 16,
            window_frames: 150,
            learning_rate: 1e-3,
            clip_grad_norm: 1.0,
            lr_patience: 1,
            early_stop_patience: 4,
            loss: Loss::default(),
            seed: 0,
            max_steps_per_epoch: None,
        }
    }
}

impl TrainConfig {
    /// Checks every value, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(GruError::Config(m));
        if self.epochs == 0 || self.epochs > 100_000 {
            return bad(format!("epochs {} must be in 1..=100000", self.epochs));
        }
        if self.batch_size == 0 || self.batch_size > 4096 {
            return bad(format!(
                "batch size {} must be in 1..=4096",
                self.batch_size
            ));
        }
        if !(2..=10_000).contains(&self.window_frames) {
            return bad(format!(
                "window {} frames must be in 2..=10000",
                self.window_frames
            ));
        }
        if !(self.learning_rate.is_finite() && self.learning_rate > 0.0 && self.learning_rate < 1.0)
        {
            return bad(format!(
                "learning rate {} must be in (0, 1)",
                self.learning_rate
            ));
        }
        if !(self.clip_grad_norm.is_finite() && self.clip_grad_norm > 0.0) {
            return bad(format!(
                "gradient clip {} must be positive",
                self.clip_grad_norm
            ));
        }
        if self.lr_patience == 0 {
            return bad("lr_patience must be at least 1".into());
        }
        self.loss.validate()
    }

    /// Whether a checkpoint made with `other` can be continued with these settings (only
    /// `epochs`, the patience values and the step cap may change).
    pub(crate) fn resumable_from(&self, other: &TrainConfig) -> bool {
        self.batch_size == other.batch_size
            && self.window_frames == other.window_frames
            && self.loss == other.loss
            && self.seed == other.seed
            && self.clip_grad_norm == other.clip_grad_norm
    }
}

/// One epoch's results.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EpochReport {
    /// Epoch number, from 1.
    pub epoch: usize,
    /// Mean training loss over the epoch's updates (dropout on).
    pub train_loss: f64,
    /// Validation loss (the training loss's weighting), when there is a validation set.
    pub val_loss: Option<f64>,
    /// Validation plain MSE.
    pub val_mse: Option<f64>,
    /// Validation mean |error| per coordinate, pixels.
    pub val_l1_px: Option<f64>,
    /// Learning rate during the epoch.
    pub learning_rate: f64,
    /// Wall time of the epoch, seconds.
    pub seconds: f64,
    /// Whether this epoch's weights became the best and were written.
    pub improved: bool,
}
