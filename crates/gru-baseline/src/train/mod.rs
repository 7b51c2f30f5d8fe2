//! Training: truncated back-propagation through time over windows of parallel streams
//! ([`plan_epoch`]), Adam with gradient clipping, validation after every epoch, the best
//! weights kept, a checkpoint for `--resume`, learning-rate halving on plateaus and early
//! stopping. Every random draw comes from the seed.

mod batch;
mod checkpoint;
mod schedule;
mod settings;

use std::path::PathBuf;
use std::time::Instant;

use candle_core::{DType, Device, Var};
use candle_nn::VarBuilder;
use net_core::rng::Rng;
use net_core::{Adam, AdamConfig};

pub use checkpoint::{checkpoint_path, Progress};
pub use schedule::{plan_epoch, Window};
pub use settings::{EpochReport, TrainConfig};

use batch::Examples;

use crate::config::Config;
use crate::data::Dataset;
use crate::error::{GruError, Result};
use crate::eval::{evaluate, Scores};
use crate::model::{GruBaseline, GruState};
use crate::norm::{MelStats, TargetSpace};
use crate::weights::{StorageDtype, TrainingRecord};

/// What to train and where to write it.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainOptions {
    /// The network's sizes.
    pub config: Config,
    /// The run's settings.
    pub train: TrainConfig,
    /// The best weights go here (checkpoint beside it, see [`checkpoint_path`]).
    pub out: PathBuf,
    /// Storage of the best weights.
    pub dtype: StorageDtype,
    /// Continue from the checkpoint beside `out`.
    pub resume: bool,
    /// The command line, for the training record.
    pub command: String,
    /// The data folder, for the training record.
    pub data: String,
}

/// Progress reports of [`train`].
#[derive(Debug, Clone, PartialEq)]
pub enum TrainEvent {
    /// Training starts (or resumes after `first_epoch - 1` epochs).
    Started {
        /// First epoch to run.
        first_epoch: usize,
        /// Last epoch.
        epochs: usize,
        /// Updates per epoch.
        steps_per_epoch: usize,
        /// Trainable parameters.
        parameters: usize,
        /// Training frames.
        train_frames: usize,
    },
    /// One update done.
    Step {
        /// Epoch, from 1.
        epoch: usize,
        /// Update within the epoch, from 1.
        step: usize,
        /// Updates in this epoch.
        steps: usize,
        /// This update's loss.
        loss: f64,
    },
    /// An epoch done.
    Epoch(EpochReport),
}

/// The outcome of [`train`].
#[derive(Debug, Clone, PartialEq)]
pub struct TrainSummary {
    /// Everything saved in the checkpoint (history, best epoch, wall time).
    pub progress: Progress,
    /// The record written into the best weights file.
    pub record: TrainingRecord,
    /// Whether early stopping ended the run.
    pub stopped_early: bool,
}

/// Trains Method 1 on `data` as `opts` says, writing the best weights to `opts.out` and a
/// checkpoint beside it after every epoch; `progress` sees every update and epoch.
pub fn train(
    data: &Dataset,
    opts: &TrainOptions,
    progress: &mut dyn FnMut(&TrainEvent),
) -> Result<TrainSummary> {
    let tcfg = &opts.train;
    opts.config.validate()?;
    tcfg.validate()?;
    if data.train.is_empty() {
        return Err(GruError::Empty("training sequences".into()));
    }
    let ckpt_path = checkpoint_path(&opts.out);
    let vars = GruBaseline::init_vars(&opts.config, tcfg.seed)?;
    let mut net = GruBaseline::new(
        &opts.config,
        VarBuilder::from_varmap(&vars, DType::F32, &Device::Cpu),
    )?;
    let mut named: Vec<(String, Var)> = vars
        .data()
        .lock()
        .map_err(|_| GruError::Config("the variable map is poisoned".into()))?
        .iter()
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    // Sorted by name: a stable order for the gradient norm's sum.
    named.sort_by(|a, b| a.0.cmp(&b.0));
    let adam_config = AdamConfig {
        learning_rate: tcfg.learning_rate,
        ..AdamConfig::default()
    };
    let mut adam = Adam::new(named.clone(), adam_config)?;
    let mut state = Progress {
        epochs_done: 0,
        adam_steps: 0,
        learning_rate: tcfg.learning_rate,
        best_loss: f64::INFINITY,
        best_epoch: 0,
        epochs_since_best: 0,
        wall_time_s: 0.0,
        history: Vec::new(),
    };
    if opts.resume {
        let ck = checkpoint::load(&ckpt_path)?;
        if ck.config != opts.config || !tcfg.resumable_from(&ck.train) {
            return Err(GruError::Weights {
                path: ckpt_path,
                reason: "the checkpoint was made with another network, loss, seed, batch or window; resume with the same settings or drop --resume".into(),
            });
        }
        for (name, var) in &named {
            let t = ck
                .tensors
                .get(&format!("param.{name}"))
                .ok_or_else(|| GruError::Weights {
                    path: ckpt_path.clone(),
                    reason: format!("checkpoint lacks parameter `{name}`"),
                })?;
            var.set(t)?;
        }
        adam.load_state(&ck.tensors)?;
        net.set_normalization(ck.mel_stats, ck.target)?;
        state = ck.progress;
        adam.config.learning_rate = state.learning_rate;
    } else {
        // Standardised targets: the head's zero bias starts at the mean pose, so the first
        // updates learn motion instead of where the body stands.
        let mel_stats = MelStats::of(data.train.iter().map(|s| s.mel_db.view()))?;
        let videos: Vec<_> = data.train.iter().map(|s| (s.video, s.image_size)).collect();
        let target = TargetSpace::of(&videos, data.train.iter().map(|s| s.joints.view()))?;
        net.set_normalization(mel_stats, target)?;
    }

    let examples = Examples::new(&net, &data.train);
    let lengths = examples.lengths();
    let steps_of = |epoch: usize| {
        let mut rng = Rng::new(tcfg.seed).fork(epoch as u64);
        let _ = rng.next_u64();
        let n = plan_epoch(&lengths, tcfg.window_frames, tcfg.batch_size, &mut rng).len();
        tcfg.max_steps_per_epoch.map_or(n, |m| n.min(m))
    };
    progress(&TrainEvent::Started {
        first_epoch: state.epochs_done + 1,
        epochs: tcfg.epochs,
        steps_per_epoch: steps_of(state.epochs_done + 1),
        parameters: opts.config.parameter_count(),
        train_frames: data.train_frames(),
    });

    let mut stopped_early = false;
    let mut record = TrainingRecord::default();
    for epoch in state.epochs_done + 1..=tcfg.epochs {
        let t0 = Instant::now();
        let mut rng = Rng::new(tcfg.seed).fork(epoch as u64);
        net.set_dropout_seed(rng.next_u64());
        let mut plan = plan_epoch(&lengths, tcfg.window_frames, tcfg.batch_size, &mut rng);
        if let Some(m) = tcfg.max_steps_per_epoch {
            plan.truncate(m);
        }
        let steps = plan.len();
        let mut carried: Option<GruState> = None;
        let mut loss_sum = 0.0;
        for (s, row) in plan.iter().enumerate() {
            let (x, y, mask) = examples.batch(row)?;
            let keep: Vec<bool> = row.iter().map(|w| w.is_some_and(|w| !w.first)).collect();
            let start = match &carried {
                Some(c) => Some(c.reset_rows(&keep)?),
                None => None,
            };
            let (pred, next) = net.forward_state(&x, start.as_ref(), true)?;
            let loss = tcfg.loss.compute(&pred, &y, Some(&mask))?;
            let value = f64::from(loss.to_scalar::<f32>()?);
            adam.step_clipped(&loss.backward()?, Some(tcfg.clip_grad_norm))?;
            carried = Some(next);
            loss_sum += value;
            progress(&TrainEvent::Step {
                epoch,
                step: s + 1,
                steps,
                loss: value,
            });
        }
        let val: Option<Scores> = if data.val.is_empty() {
            None
        } else {
            Some(evaluate(&net, &data.val, &tcfg.loss)?)
        };
        let train_loss = loss_sum / steps.max(1) as f64;
        let criterion = val.map_or(train_loss, |v| v.loss);
        let improved = criterion < state.best_loss;
        let lr_used = adam.config.learning_rate;
        state.epochs_done = epoch;
        state.adam_steps = adam.steps();
        state.wall_time_s += t0.elapsed().as_secs_f64();
        if improved {
            state.best_loss = criterion;
            state.best_epoch = epoch;
            state.epochs_since_best = 0;
        } else {
            state.epochs_since_best += 1;
            if state.epochs_since_best.is_multiple_of(tcfg.lr_patience) {
                adam.config.learning_rate = (adam.config.learning_rate * 0.5).max(1e-5);
            }
        }
        state.learning_rate = adam.config.learning_rate;
        let report = EpochReport {
            epoch,
            train_loss,
            val_loss: val.map(|v| v.loss),
            val_mse: val.map(|v| v.mse),
            val_l1_px: val.map(|v| v.l1_px),
            learning_rate: lr_used,
            seconds: t0.elapsed().as_secs_f64(),
            improved,
        };
        state.history.push(report.clone());
        record = TrainingRecord {
            command: opts.command.clone(),
            data: opts.data.clone(),
            seed: tcfg.seed,
            epochs: epoch,
            best_epoch: state.best_epoch,
            val_loss: state.best_loss,
            weighted_loss: tcfg.loss.is_weighted(),
            train_frames: data.train_frames(),
            wall_time_s: state.wall_time_s,
        };
        if improved {
            net.save(&opts.out, opts.dtype, Some(&record))?;
        }
        checkpoint::save(&ckpt_path, &net, &adam, tcfg, &state)?;
        progress(&TrainEvent::Epoch(report));
        if tcfg.early_stop_patience > 0 && state.epochs_since_best >= tcfg.early_stop_patience {
            stopped_early = true;
            break;
        }
    }
    Ok(TrainSummary {
        progress: state,
        record,
        stopped_early,
    })
}
