//! Training on arousal-labelled tracks: 20-step windows every `window_hop` frames over the
//! annotated part of each training track, masked MSE, Adam with a warm-up + cosine learning
//! rate ([`LrSchedule`]; seeded initialisation, order and dropout), early stopping on the
//! validation Pearson r of whole-track (overlap-averaged) predictions, best weights written to
//! the output whenever they improve, and a checkpoint (`NAME.ckpt.safetensors`) after every
//! epoch for `resume`.

use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

use candle_core::{DType, Device, Tensor};
use candle_nn::{VarBuilder, VarMap};
use net_core::rng::Rng;
use net_core::{
    checkpoint_path, resume_from_checkpoint, save_checkpoint, set_band_statistics, vars, Adam,
    AdamConfig, LrSchedule, TrainState,
};
use serde::{Deserialize, Serialize};

use crate::data::{ArousalSplits, ArousalTrack};
use crate::error::{EmotionError, Result};
use crate::estimator::{ArousalEstimator, FORMAT_VERSION};
use crate::evaluate::score;
use crate::model::{Config, EmotionNet};
use crate::windows::{training_windows, window_batch};

pub use crate::windows::{recalibrate_batch_norm, CALIBRATION_WINDOWS};

/// Training settings (JSON: any subset of the fields; unknown fields are refused so that a
/// typo is not silently ignored).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TrainConfig {
    /// The network's shape.
    pub model: Config,
    /// Maximum epochs.
    pub epochs: usize,
    /// Stop after this many epochs without a better validation r.
    pub patience: usize,
    /// Seed of initialisation, order and dropout.
    pub seed: u64,
    /// Adam's peak learning rate.
    pub learning_rate: f64,
    /// How the learning rate moves over the steps.
    pub schedule: LrSchedule,
    /// Windows per step.
    pub batch_windows: usize,
    /// Frames between training windows.
    pub window_hop: usize,
    /// Augmentation: each training window's mel bands are shifted by a random whole number
    /// of bands in `-band_shift_max..=band_shift_max` (edge bands repeated), a rough
    /// transposition; 0 = off.
    pub band_shift_max: usize,
    /// Re-estimate the batch-norm running statistics with dropout off after every epoch,
    /// before validation ([`recalibrate_batch_norm`]).
    pub recalibrate_batch_norm: bool,
    /// Cap on steps per epoch (tests).
    pub max_steps_per_epoch: Option<usize>,
    /// Free text stored with the weights (e.g. the data folder).
    pub data_description: String,
}

impl Default for TrainConfig {
    fn default() -> Self {
        Self {
            model: Config::default(),
            epochs: 40,
            patience: 10,
            seed: 1,
            learning_rate: 2e-2,
            schedule: LrSchedule::WarmupCosine {
                warmup_fraction: 0.03,
                final_fraction: 0.02,
            },
            batch_windows: 32,
            window_hop: 2,
            band_shift_max: 0,
            recalibrate_batch_norm: false,
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
    /// Mean training loss (MSE) of this epoch so far.
    pub loss: f32,
    /// The learning rate of the last step.
    pub learning_rate: f64,
    /// Validation Pearson r of the epoch just finished (`None` during the epoch).
    pub val_r: Option<f64>,
    /// Best validation r so far.
    pub best_r: f64,
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
    /// Validation Pearson r of the kept weights.
    pub best_val_r: f64,
    /// Mean training loss per epoch.
    pub epoch_losses: Vec<f32>,
    /// Whether early stopping ended training.
    pub stopped_early: bool,
    /// Training tracks.
    pub train_tracks: usize,
    /// Training audio in minutes.
    pub train_minutes: f64,
    /// Wall time of this run in seconds.
    pub wall_s: f64,
}

/// Format name of checkpoints.
pub const CHECKPOINT_FORMAT: &str = "violin-skeleton/emotion-net-checkpoint";

fn check_tracks(tracks: &[ArousalTrack], what: &str, bands: usize) -> Result<()> {
    if tracks.iter().all(|t| t.arousal.is_empty()) {
        return Err(EmotionError::Input(format!(
            "no annotated {what} tracks: the data needs train and validation items"
        )));
    }
    for t in tracks {
        net_core::frames::check_mel(t.mel_db.view(), bands)
            .map_err(|e| EmotionError::Input(format!("{}: {e}", t.name)))?;
        if t.arousal.iter().any(|v| !v.is_finite()) {
            return Err(EmotionError::Input(format!(
                "{}: non-finite arousal target",
                t.name
            )));
        }
    }
    Ok(())
}

/// All model tensors to save: trainable and normalisation variables, with the batch-norm
/// running statistics taken from the network.
fn model_tensors(varmap: &VarMap, net: &EmotionNet) -> Result<Vec<(String, Tensor)>> {
    let running: HashMap<String, Tensor> = net.running_stats().into_iter().collect();
    vars::var_tensors(varmap)
        .into_iter()
        .map(|(n, t)| {
            let t = running.get(&n).cloned().unwrap_or(t);
            Ok((n, t.copy()?))
        })
        .collect()
}

/// Trains the arousal network (module docs); `progress` is called after every step and at
/// the end of every epoch.
pub fn train(
    data: &ArousalSplits,
    cfg: &TrainConfig,
    out: &Path,
    resume: bool,
    progress: &mut dyn FnMut(&TrainProgress),
) -> Result<TrainReport> {
    let started = Instant::now();
    let mcfg = &cfg.model;
    mcfg.validate()?;
    if cfg.batch_windows == 0 || cfg.window_hop == 0 {
        return Err(EmotionError::Config(
            "batch_windows and window_hop must be positive".into(),
        ));
    }
    check_tracks(&data.train, "training", mcfg.n_mels)?;
    check_tracks(&data.val, "validation", mcfg.n_mels)?;
    // Inference normalises each recording's level the same way (`predict_with`).
    let train_tracks: Vec<ArousalTrack> = data
        .train
        .iter()
        .map(|t| ArousalTrack {
            mel_db: mcfg.gain_norm.apply(t.mel_db.view()),
            ..t.clone()
        })
        .collect();
    let train_tracks = &train_tracks[..];
    let varmap = VarMap::new();
    let net = EmotionNet::new(
        mcfg,
        VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu),
    )?;
    vars::init_seeded(&varmap, cfg.seed, |name, dims| {
        if name.starts_with("norm.")
            || name.contains("running_")
            || name.contains("gamma")
            || name.contains("beta")
        {
            None
        } else if name.contains("bias") {
            Some(0.0)
        } else {
            let fan_in: usize = dims.iter().skip(1).product();
            Some((3.0 / fan_in.max(1) as f64).sqrt())
        }
    })?;
    set_band_statistics(
        &varmap,
        train_tracks.iter().map(|t| t.mel_db.view()),
        mcfg.n_mels,
    )?;
    let frozen = |n: &str| n.starts_with("norm.") || n.contains("running_");
    let mut adam = Adam::new(
        vars::trainable_vars(&varmap, frozen),
        AdamConfig {
            learning_rate: cfg.learning_rate,
            ..AdamConfig::default()
        },
    )?;
    let ckpt = checkpoint_path(out);
    let mut state = TrainState::new(mcfg.clone(), -2.0);
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

    let pads: Vec<f32> = train_tracks
        .iter()
        .map(|tr| tr.mel_db.iter().copied().fold(f32::INFINITY, f32::min))
        .collect();
    let windows = training_windows(train_tracks, mcfg.steps, cfg.window_hop);
    let steps_per_epoch = windows
        .len()
        .div_ceil(cfg.batch_windows)
        .min(cfg.max_steps_per_epoch.unwrap_or(usize::MAX));
    let mut stopped_early = false;
    let mut epoch = state.next_epoch;
    while epoch < cfg.epochs {
        let mut rng = Rng::new(cfg.seed).fork(epoch as u64 + 1);
        net.dropout_rng().reseed(rng.next_u64());
        let mut order = windows.clone();
        for i in (1..order.len()).rev() {
            let j = (rng.next_u64() % (i as u64 + 1)) as usize;
            order.swap(i, j);
        }
        let mut loss_sum = 0.0f64;
        let mut lr = cfg.learning_rate;
        for (step, batch) in order
            .chunks(cfg.batch_windows)
            .take(steps_per_epoch)
            .enumerate()
        {
            lr = cfg.schedule.rate(
                cfg.learning_rate,
                epoch * steps_per_epoch + step,
                steps_per_epoch,
                cfg.epochs,
            );
            adam.config.learning_rate = lr;
            let shift = cfg.band_shift_max as i64;
            let shifts: Vec<i64> = batch.iter().map(|_| rng.int(-shift, shift)).collect();
            let (xt, yt, mt) = window_batch(train_tracks, &pads, batch, &shifts, mcfg)?;
            let pred = net.forward_t(&xt, true)?;
            let n = mt.sum_all()?.to_scalar::<f32>()?.max(1.0);
            let loss = ((pred - yt)?.sqr()? * &mt)?
                .sum_all()?
                .affine(1.0 / f64::from(n), 0.0)?;
            let value = loss.to_scalar::<f32>()?;
            if !value.is_finite() {
                return Err(EmotionError::Input(format!(
                    "training diverged (loss {value}); lower the learning rate"
                )));
            }
            adam.backward_step(&loss)?;
            loss_sum += f64::from(value);
            progress(&TrainProgress {
                epoch,
                epochs: cfg.epochs,
                step: step + 1,
                steps: steps_per_epoch,
                loss: (loss_sum / (step + 1) as f64) as f32,
                learning_rate: lr,
                val_r: None,
                best_r: state.best_metric.max(0.0),
                elapsed_s: started.elapsed().as_secs_f64(),
            });
        }
        let epoch_loss = (loss_sum / steps_per_epoch.max(1) as f64) as f32;
        if cfg.recalibrate_batch_norm {
            recalibrate_batch_norm(&net, &data.train)?;
        }
        let (r, _) = score(&net, &data.val)?;
        if state.end_epoch(epoch, epoch_loss, r) {
            ArousalEstimator::from_tensors(mcfg, model_tensors(&varmap, &net)?, String::new())?
                .save(out)?;
        }
        progress(&TrainProgress {
            epoch,
            epochs: cfg.epochs,
            step: steps_per_epoch,
            steps: steps_per_epoch,
            loss: epoch_loss,
            learning_rate: lr,
            val_r: Some(r),
            best_r: state.best_metric,
            elapsed_s: started.elapsed().as_secs_f64(),
        });
        epoch += 1;
        save_checkpoint(
            &ckpt,
            CHECKPOINT_FORMAT,
            FORMAT_VERSION,
            model_tensors(&varmap, &net)?,
            &adam,
            &state,
        )?;
        if state.should_stop(cfg.patience) {
            stopped_early = true;
            break;
        }
    }
    let frames: usize = data.train.iter().map(|t| t.mel_db.nrows()).sum();
    let report = TrainReport {
        epochs_run: state.next_epoch,
        best_epoch: state.best_epoch,
        best_val_r: state.best_metric,
        epoch_losses: state.epoch_losses.clone(),
        stopped_early,
        train_tracks: data.train.len(),
        train_minutes: frames as f64 / 2.0 / 60.0,
        wall_s: started.elapsed().as_secs_f64(),
    };
    let mut best = ArousalEstimator::load(out)?;
    let info = serde_json::json!({
        "data": cfg.data_description,
        "seed": cfg.seed,
        "train_tracks": report.train_tracks,
        "train_minutes": (report.train_minutes * 10.0).round() / 10.0,
        "epochs_run": report.epochs_run,
        "best_epoch": report.best_epoch,
        "val_pearson_r": report.best_val_r,
        "wall_s_this_run": report.wall_s.round(),
    });
    best.set_training_info(info.to_string());
    best.save(out)?;
    Ok(report)
}
