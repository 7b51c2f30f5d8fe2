//! Training: every frame of every training recording is a window centred on it; windows are
//! drawn as runs of consecutive frames ("sequences", [`crate::batch`]) so the phase tree
//! shares the convolution work (module docs of [`crate::model`]).
//!
//! * **Imbalance**: a change's label is widened to ±`label_radius_frames` (default 1, i.e.
//!   3 positive frames per change, which also absorbs ±1-frame label jitter) and positive
//!   frames are weighted by `negatives / positives` in the cross-entropy (balanced), so a
//!   probability of 0.5 is the natural decision point; peak picking then keeps one frame per
//!   change. Negatives next to a slurred note change (a new note, no bow change) weigh
//!   `slur_weight`: they are the mistakes the detector is most tempted to make.
//! * **Optimiser**: Adam; the learning rate warms up linearly over the first 5 % of all
//!   steps and follows a half cosine down to 2 % of its peak at the last epoch
//!   ([`LrSchedule`]); seeded initialisation, order, augmentation and dropout.
//! * **Augmentation**: each sequence's level is shifted by up to ±6 dB ([`Augment`]).
//! * **Early stopping** on validation F1 (±2 frames, decoder tuned on the validation set after
//!   each epoch); the best weights are written to the output file whenever they improve, and
//!   a checkpoint (`NAME.ckpt.safetensors`: weights, Adam moments, progress) after every
//!   epoch so `resume` continues where training stopped. The kept weights store their tuned
//!   decoder (threshold and minimum spacing).

use std::path::Path;
use std::time::Instant;

use candle_core::{Device, Tensor};
use candle_nn::VarMap;
use net_core::rng::Rng;
use net_core::{
    checkpoint_path, resume_from_checkpoint, save_checkpoint, set_band_statistics, vars, Adam,
    AdamConfig, LrSchedule, TrainState,
};
use serde::{Deserialize, Serialize};

use crate::batch::{batch_targets, frame_labels, plan_epoch, sequence_input, Augment, Weighting};
use crate::data::{Recording, Splits};
use crate::decode::Decoder;
use crate::detector::{BowChangeDetector, FORMAT_VERSION};
use crate::error::{NetError, Result};
use crate::infer::sequence_frames;
use crate::metrics::{tune_decoder, validation_f1};
use crate::model::{BowingNet, Config, WeightInit, PHASES};
use net_core::frames::pad_value;
use net_core::nn::weighted_cross_entropy;

/// Training settings (JSON: any subset of the fields; unknown fields are refused so that a
/// typo is not silently ignored).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TrainConfig {
    /// The network's shape.
    pub model: Config,
    /// Maximum epochs (passes over every training frame); the schedule spans them.
    pub epochs: usize,
    /// Stop after this many epochs without a better validation F1.
    pub patience: usize,
    /// Seed of initialisation, order, augmentation and dropout.
    pub seed: u64,
    /// Adam's peak learning rate.
    pub learning_rate: f64,
    /// How the learning rate moves over the steps.
    pub schedule: LrSchedule,
    /// Sequences per step.
    pub batch_sequences: usize,
    /// Consecutive windows per sequence (a multiple of 8).
    pub sequence_windows: usize,
    /// Frames on each side of a change also labelled "change".
    pub label_radius_frames: usize,
    /// Weight of positive frames; `None` = negatives / positives.
    pub positive_weight: Option<f32>,
    /// Weight of negative frames within ±`label_radius_frames` of a slurred note change.
    pub slur_weight: f32,
    /// Input augmentation of training sequences.
    pub augment: Augment,
    /// Initialisation of the weights.
    pub init: WeightInit,
    /// Cap on steps per epoch (tests); `None` = all sequences.
    pub max_steps_per_epoch: Option<usize>,
    /// Free text stored with the weights (e.g. the data folder).
    pub data_description: String,
}

impl Default for TrainConfig {
    fn default() -> Self {
        Self {
            model: Config::default(),
            epochs: 12,
            patience: 4,
            seed: 1,
            learning_rate: 2e-3,
            schedule: LrSchedule::WarmupCosine {
                warmup_fraction: 0.05,
                final_fraction: 0.02,
            },
            batch_sequences: 8,
            sequence_windows: 128,
            label_radius_frames: 1,
            positive_weight: None,
            slur_weight: 2.0,
            augment: Augment::default(),
            init: WeightInit::GlorotUniform,
            max_steps_per_epoch: None,
            data_description: String::new(),
        }
    }
}

/// What the progress callback is told.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainProgress {
    /// Epoch (0-based).
    pub epoch: usize,
    /// Maximum epochs.
    pub epochs: usize,
    /// Steps done in this epoch.
    pub step: usize,
    /// Steps in this epoch.
    pub steps: usize,
    /// Mean training loss of this epoch so far.
    pub loss: f32,
    /// The learning rate of the last step.
    pub learning_rate: f64,
    /// Validation F1 (±2 frames, decoder tuned on validation) of the epoch just finished
    /// (`None` during the epoch).
    pub val_f1: Option<f64>,
    /// Best validation F1 so far.
    pub best_f1: f64,
    /// Seconds since this run started.
    pub elapsed_s: f64,
}

/// The result of [`train`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainReport {
    /// Epochs completed (including ones before a resume).
    pub epochs_run: usize,
    /// Epoch (0-based) of the kept weights.
    pub best_epoch: usize,
    /// Validation F1 (±2) of the kept weights with the default decoder (threshold 0.5).
    pub best_val_f1: f64,
    /// Validation F1 (±2) of the kept weights with their tuned decoder (the early-stopping
    /// metric).
    pub tuned_val_f1: f64,
    /// The tuned decoder stored in the weights.
    pub decoder: Decoder,
    /// Mean training loss per epoch.
    pub epoch_losses: Vec<f32>,
    /// Whether early stopping ended training.
    pub stopped_early: bool,
    /// Positive-frame weight used.
    pub positive_weight: f32,
    /// Training recordings.
    pub train_recordings: usize,
    /// Total training audio in minutes.
    pub train_minutes: f64,
    /// Wall time of this run in seconds.
    pub wall_s: f64,
}

/// Format name of checkpoints.
pub const CHECKPOINT_FORMAT: &str = "violin-skeleton/bowing-net-checkpoint";

fn check_recordings(recs: &[Recording], what: &str, bands: usize) -> Result<()> {
    if recs.is_empty() {
        return Err(NetError::Input(format!(
            "no {what} recordings: the data needs train and validation items"
        )));
    }
    for r in recs {
        net_core::frames::check_mel(r.mel_db.view(), bands)
            .map_err(|e| NetError::Input(format!("{}: {e}", r.name)))?;
    }
    Ok(())
}

fn check_config(cfg: &TrainConfig) -> Result<()> {
    cfg.model.validate()?;
    if cfg.sequence_windows == 0
        || !cfg.sequence_windows.is_multiple_of(PHASES)
        || cfg.batch_sequences == 0
    {
        return Err(NetError::Config(format!(
            "sequence_windows must be a positive multiple of {PHASES} and batch_sequences positive"
        )));
    }
    let bad_lr = !cfg.learning_rate.is_finite() || cfg.learning_rate <= 0.0;
    let bad_slur = !cfg.slur_weight.is_finite() || cfg.slur_weight < 0.0;
    if cfg.epochs == 0 || bad_lr || bad_slur {
        return Err(NetError::Config(
            "epochs and the learning rate must be positive, slur_weight not negative".into(),
        ));
    }
    Ok(())
}

/// A fresh network of `cfg` with seeded initialisation and the input statistics of
/// `train`.
fn init_network(cfg: &TrainConfig, train: &[Recording]) -> Result<(VarMap, BowingNet)> {
    let (varmap, net) = BowingNet::seeded(&cfg.model, cfg.init, cfg.seed)?;
    set_band_statistics(
        &varmap,
        train.iter().map(|r| r.mel_db.view()),
        cfg.model.n_mels,
    )?;
    Ok((varmap, net))
}

/// Trains a bowing network on `data.train`, early-stopping on `data.val`, writing the best
/// weights to `out` (and a checkpoint beside it). With `resume`, continues from the
/// checkpoint. `progress` is called after every step and at the end of every epoch.
pub fn train(
    data: &Splits,
    cfg: &TrainConfig,
    out: &Path,
    resume: bool,
    progress: &mut dyn FnMut(&TrainProgress),
) -> Result<TrainReport> {
    let started = Instant::now();
    check_config(cfg)?;
    let mcfg = &cfg.model;
    check_recordings(&data.train, "training", mcfg.n_mels)?;
    check_recordings(&data.val, "validation", mcfg.n_mels)?;
    let widened: Vec<Vec<u8>> = data
        .train
        .iter()
        .map(|r| crate::batch::positive_frames(r, cfg.label_radius_frames))
        .collect();
    let positives: usize = widened.iter().flatten().filter(|&&v| v == 1).count();
    let total: usize = widened.iter().map(Vec::len).sum();
    if positives == 0 {
        return Err(NetError::Input(
            "the training recordings have no bow change".into(),
        ));
    }
    let positive_weight = cfg
        .positive_weight
        .unwrap_or(((total - positives) as f32 / positives as f32).max(1.0));
    let weighting = Weighting {
        label_radius_frames: cfg.label_radius_frames,
        positive_weight,
        slur_weight: cfg.slur_weight,
    };
    let labels: Vec<_> = data
        .train
        .iter()
        .map(|r| frame_labels(r, &weighting))
        .collect();

    let (varmap, net) = init_network(cfg, &data.train)?;
    let params = vars::trainable_vars(&varmap, |n| n.starts_with("norm."));
    let mut adam = Adam::new(
        params,
        AdamConfig {
            learning_rate: cfg.learning_rate,
            ..AdamConfig::default()
        },
    )?;
    let ckpt = checkpoint_path(out);
    let mut state = TrainState::new(mcfg.clone(), -1.0);
    if resume {
        state = resume_from_checkpoint(
            &ckpt,
            CHECKPOINT_FORMAT,
            FORMAT_VERSION,
            mcfg,
            &varmap,
            &mut adam,
        )?;
    }

    let pads: Vec<f32> = data
        .train
        .iter()
        .map(|r| pad_value(r.mel_db.view()))
        .collect();
    let frames: Vec<usize> = data.train.iter().map(|r| r.mel_db.nrows()).collect();
    let seq_len = sequence_frames(&net, cfg.sequence_windows);
    let center = mcfg.center_offset() as isize;
    let bands = mcfg.n_mels;
    let seqs_per_epoch: usize = frames
        .iter()
        .map(|&f| f.div_ceil(cfg.sequence_windows) + 1)
        .sum();
    let mut steps_per_epoch = seqs_per_epoch.div_ceil(cfg.batch_sequences);
    if let Some(cap) = cfg.max_steps_per_epoch {
        steps_per_epoch = steps_per_epoch.min(cap);
    }
    let mut stopped_early = false;
    let mut epoch = state.next_epoch;
    while epoch < cfg.epochs {
        let mut rng = Rng::new(cfg.seed).fork(epoch as u64 + 1);
        net.dropout_rng().reseed(rng.next_u64());
        let mut aug_rng = rng.fork(7);
        let seqs = plan_epoch(&frames, cfg.sequence_windows, &mut rng);
        let steps = seqs
            .len()
            .div_ceil(cfg.batch_sequences)
            .min(steps_per_epoch);
        let mut loss_sum = 0.0f64;
        let mut lr = cfg.learning_rate;
        for (step, batch) in seqs.chunks(cfg.batch_sequences).take(steps).enumerate() {
            lr = cfg.schedule.rate(
                cfg.learning_rate,
                epoch * steps_per_epoch + step,
                steps_per_epoch,
                cfg.epochs,
            );
            adam.config.learning_rate = lr;
            let mut buf = vec![0.0f32; batch.len() * seq_len * bands];
            for (&(ri, start), dst) in batch.iter().zip(buf.chunks_exact_mut(seq_len * bands)) {
                let mel = data.train[ri].mel_db.view();
                sequence_input(
                    mel,
                    start - center,
                    pads[ri],
                    &cfg.augment,
                    &mut aug_rng,
                    dst,
                );
            }
            let x = Tensor::from_vec(buf, (batch.len(), seq_len, bands), &Device::Cpu)?;
            let logits = net.sequence_logits(&x, true)?;
            let (rows, windows, _) = logits.dims3()?;
            let (targets, weights) =
                batch_targets(&labels, batch, rows, windows, cfg.sequence_windows);
            let n = rows * windows;
            let loss = weighted_cross_entropy(
                &logits.reshape((n, 2))?,
                &Tensor::from_vec(targets, n, &Device::Cpu)?,
                &Tensor::from_vec(weights, n, &Device::Cpu)?,
            )?;
            let value = loss.to_scalar::<f32>()?;
            if !value.is_finite() {
                return Err(NetError::Input(format!(
                    "training diverged (loss {value}) at epoch {epoch}; lower the learning rate"
                )));
            }
            adam.backward_step(&loss)?;
            loss_sum += f64::from(value);
            progress(&TrainProgress {
                epoch,
                epochs: cfg.epochs,
                step: step + 1,
                steps,
                loss: (loss_sum / (step + 1) as f64) as f32,
                learning_rate: lr,
                val_f1: None,
                best_f1: state.best_metric.max(0.0),
                elapsed_s: started.elapsed().as_secs_f64(),
            });
        }
        let epoch_loss = (loss_sum / steps.max(1) as f64) as f32;
        let (_, probs) = validation_f1(&net, &data.val, &Decoder::default())?;
        let (decoder, f1) = tune_decoder(&probs, &data.val);
        if state.end_epoch(epoch, epoch_loss, f1) {
            BowChangeDetector::from_varmap(mcfg, &varmap, decoder, String::new())?.save(out)?;
        }
        progress(&TrainProgress {
            epoch,
            epochs: cfg.epochs,
            step: steps,
            steps,
            loss: epoch_loss,
            learning_rate: lr,
            val_f1: Some(f1),
            best_f1: state.best_metric,
            elapsed_s: started.elapsed().as_secs_f64(),
        });
        epoch += 1;
        save_checkpoint(
            &ckpt,
            CHECKPOINT_FORMAT,
            FORMAT_VERSION,
            vars::var_tensors(&varmap),
            &adam,
            &state,
        )?;
        if state.should_stop(cfg.patience) {
            stopped_early = true;
            break;
        }
    }

    let mut best = BowChangeDetector::load(out)?;
    let (default_f1, _) = validation_f1(best.net(), &data.val, &Decoder::default())?;
    let train_minutes = total as f64 / 30.0 / 60.0;
    let report = TrainReport {
        epochs_run: state.next_epoch,
        best_epoch: state.best_epoch,
        best_val_f1: default_f1,
        tuned_val_f1: state.best_metric,
        decoder: best.decoder(),
        epoch_losses: state.epoch_losses.clone(),
        stopped_early,
        positive_weight,
        train_recordings: data.train.len(),
        train_minutes,
        wall_s: started.elapsed().as_secs_f64(),
    };
    let info = serde_json::json!({
        "data": cfg.data_description,
        "seed": cfg.seed,
        "train_recordings": report.train_recordings,
        "train_minutes": (train_minutes * 10.0).round() / 10.0,
        "epochs_run": report.epochs_run,
        "best_epoch": report.best_epoch,
        "val_f1_2frames": report.tuned_val_f1,
        "wall_s_this_run": report.wall_s.round(),
    });
    best.set_training_info(info.to_string());
    best.save(out)?;
    Ok(report)
}
