//! Training: every frame of every training recording is a window centred on it; windows are
//! drawn as runs of consecutive frames ("sequences") so the phase tree shares the
//! convolution work (module docs of [`crate::model`]).
//!
//! * **Imbalance**: a change's label is widened to ±`label_radius_frames` (default 1, i.e.
//!   3 positive frames per change, which also absorbs ±1-frame label jitter) and positive
//!   frames are weighted by `negatives / positives` in the cross-entropy (balanced), so a
//!   probability of 0.5 is the natural decision point; peak picking then keeps one frame per
//!   change.
//! * **Optimiser**: Adam, learning rate × `lr_decay_per_epoch` each epoch; seeded
//!   initialisation, order and dropout.
//! * **Early stopping** on validation F1 (±2 frames, default decoder); the best weights are
//!   written to the output file whenever they improve, and a checkpoint
//!   (`NAME.ckpt.safetensors`: weights, Adam moments, progress) after every epoch so
//!   `resume` continues where training stopped.
//! * At the end the decoder's threshold and minimum spacing are tuned on the validation set
//!   and stored in the weights file.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use candle_core::{Device, Tensor};
use candle_nn::{VarBuilder, VarMap};
use corpus::rng::Rng;
use serde::{Deserialize, Serialize};

use crate::data::{Recording, Splits};
use crate::decode::tune_decoder;
use crate::decode::Decoder;
use crate::detector::BowChangeDetector;
use crate::error::{NetError, Result};
use crate::infer::{copy_frames, pad_value, sequence_frames};
use crate::metrics::validation_f1;
use crate::model::{window_start, BowingNet, Config, DTYPE, PHASES};
use crate::nn::{store, weighted_cross_entropy, Adam, AdamConfig};

/// Training settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct TrainConfig {
    /// The network's shape.
    pub model: Config,
    /// Maximum epochs (passes over every training frame).
    pub epochs: usize,
    /// Stop after this many epochs without a better validation F1.
    pub patience: usize,
    /// Seed of initialisation, order and dropout.
    pub seed: u64,
    /// Adam's initial learning rate.
    pub learning_rate: f64,
    /// Learning-rate factor per epoch.
    pub lr_decay_per_epoch: f64,
    /// Sequences per step.
    pub batch_sequences: usize,
    /// Consecutive windows per sequence (a multiple of 8).
    pub sequence_windows: usize,
    /// Frames on each side of a change also labelled "change".
    pub label_radius_frames: usize,
    /// Weight of positive frames; `None` = negatives / positives.
    pub positive_weight: Option<f32>,
    /// Cap on steps per epoch (tests); `None` = all sequences.
    pub max_steps_per_epoch: Option<usize>,
    /// Free text stored with the weights (e.g. the data folder).
    pub data_description: String,
}

impl Default for TrainConfig {
    fn default() -> Self {
        Self {
            model: Config::default(),
            epochs: 30,
            patience: 5,
            seed: 1,
            learning_rate: 1e-3,
            lr_decay_per_epoch: 0.93,
            batch_sequences: 8,
            sequence_windows: 128,
            label_radius_frames: 1,
            positive_weight: None,
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
    /// Validation F1 (±2 frames) of the epoch just finished (`None` during the epoch).
    pub val_f1: Option<f64>,
    /// Best validation F1 so far.
    pub best_f1: f64,
}

/// The result of [`train`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainReport {
    /// Epochs completed (including ones before a resume).
    pub epochs_run: usize,
    /// Epoch (0-based) of the kept weights.
    pub best_epoch: usize,
    /// Validation F1 (±2) of the kept weights with the default decoder.
    pub best_val_f1: f64,
    /// Validation F1 (±2) with the tuned decoder.
    pub tuned_val_f1: f64,
    /// The tuned decoder stored in the weights.
    pub decoder: Decoder,
    /// Mean training loss per epoch.
    pub epoch_losses: Vec<f32>,
    /// Whether early stopping ended training.
    pub stopped_early: bool,
    /// Positive-frame weight used.
    pub positive_weight: f32,
    /// Training recordings and minutes.
    pub train_recordings: usize,
    /// Total training audio in minutes.
    pub train_minutes: f64,
    /// Wall time of this run in seconds.
    pub wall_s: f64,
}

/// Format name of checkpoints.
pub const CHECKPOINT_FORMAT: &str = "violin-skeleton/bowing-net-checkpoint";

/// The checkpoint written beside `out`: `W.safetensors` → `W.ckpt.safetensors`.
pub fn checkpoint_path(out: &Path) -> PathBuf {
    out.with_extension("ckpt.safetensors")
}

#[derive(Debug, Clone, Serialize, Deserialize)]
struct CheckpointState {
    next_epoch: usize,
    best_f1: f64,
    best_epoch: usize,
    since_best: usize,
    epoch_losses: Vec<f32>,
    model: Config,
}

fn widened_labels(rec: &Recording, radius: usize) -> Vec<u8> {
    let n = rec.mel_db.nrows();
    let mut out = vec![0u8; n];
    for &c in &rec.changes {
        let end = (c + radius + 1).min(n);
        if let Some(span) = out.get_mut(c.saturating_sub(radius)..end) {
            span.fill(1);
        }
    }
    out
}

/// Keras's default initialisation (Glorot/Xavier uniform) bound for a weight of shape
/// `(out, in, k…)`: `sqrt(6 / (fan_in + fan_out))`.
pub fn glorot_bound(dims: &[usize]) -> f64 {
    let receptive: usize = dims.iter().skip(2).product();
    let fan_out = dims.first().copied().unwrap_or(1) * receptive.max(1);
    let fan_in = dims.get(1).copied().unwrap_or(1) * receptive.max(1);
    (6.0 / (fan_in + fan_out).max(1) as f64).sqrt()
}

/// Per-band mean and standard deviation (floored at 1e-3) over all frames.
pub fn band_statistics(recs: &[Recording], bands: usize) -> (Vec<f32>, Vec<f32>) {
    let mut sum = vec![0.0f64; bands];
    let mut sq = vec![0.0f64; bands];
    let mut n = 0usize;
    for r in recs {
        for row in r.mel_db.rows() {
            for (k, &v) in row.iter().enumerate().take(bands) {
                sum[k] += f64::from(v);
                sq[k] += f64::from(v) * f64::from(v);
            }
            n += 1;
        }
    }
    let n = n.max(1) as f64;
    let mean: Vec<f32> = sum.iter().map(|s| (s / n) as f32).collect();
    let std: Vec<f32> = sq
        .iter()
        .zip(&sum)
        .map(|(q, s)| ((q / n - (s / n).powi(2)).max(0.0).sqrt().max(1e-3)) as f32)
        .collect();
    (mean, std)
}

fn check_recordings(recs: &[Recording], what: &str, bands: usize) -> Result<()> {
    if recs.is_empty() {
        return Err(NetError::Input(format!(
            "no {what} recordings: the data needs train and validation items"
        )));
    }
    for r in recs {
        crate::features::check_mel(r.mel_db.view(), bands)
            .map_err(|e| NetError::Input(format!("{}: {e}", r.name)))?;
    }
    Ok(())
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
    let mcfg = &cfg.model;
    mcfg.validate()?;
    if cfg.sequence_windows == 0 || cfg.sequence_windows % PHASES != 0 || cfg.batch_sequences == 0 {
        return Err(NetError::Config(format!(
            "sequence_windows must be a positive multiple of {PHASES} and batch_sequences positive"
        )));
    }
    check_recordings(&data.train, "training", mcfg.n_mels)?;
    check_recordings(&data.val, "validation", mcfg.n_mels)?;
    let labels: Vec<Vec<u8>> = data
        .train
        .iter()
        .map(|r| widened_labels(r, cfg.label_radius_frames))
        .collect();
    let positives: usize = labels
        .iter()
        .map(|l| l.iter().filter(|&&v| v == 1).count())
        .sum();
    let total: usize = labels.iter().map(Vec::len).sum();
    if positives == 0 {
        return Err(NetError::Input(
            "the training recordings have no bow change".into(),
        ));
    }
    let positive_weight = cfg
        .positive_weight
        .unwrap_or(((total - positives) as f32 / positives as f32).max(1.0));

    let varmap = VarMap::new();
    let net = BowingNet::new(mcfg, VarBuilder::from_varmap(&varmap, DTYPE, &Device::Cpu))?;
    store::init_seeded(&varmap, cfg.seed, |name, dims| {
        if name.starts_with("norm.") {
            None
        } else if name.ends_with("bias") {
            Some(0.0)
        } else {
            Some(glorot_bound(dims))
        }
    })?;
    let (mean, std) = band_statistics(&data.train, mcfg.n_mels);
    let mut norm = HashMap::new();
    norm.insert(
        "norm.mean".to_string(),
        Tensor::new(mean.as_slice(), &Device::Cpu)?,
    );
    norm.insert(
        "norm.std".to_string(),
        Tensor::new(std.as_slice(), &Device::Cpu)?,
    );
    set_vars(&varmap, &norm)?;
    let params = store::trainable_vars(&varmap, |n| n.starts_with("norm."));
    let mut adam = Adam::new(
        params,
        AdamConfig {
            learning_rate: cfg.learning_rate,
            ..AdamConfig::default()
        },
    )?;

    let ckpt = checkpoint_path(out);
    let mut state = CheckpointState {
        next_epoch: 0,
        best_f1: -1.0,
        best_epoch: 0,
        since_best: 0,
        epoch_losses: Vec::new(),
        model: mcfg.clone(),
    };
    if resume {
        let file = store::read(&ckpt)?;
        file.check_format(&ckpt, CHECKPOINT_FORMAT, crate::detector::FORMAT_VERSION)?;
        state = serde_json::from_str(file.meta("state", &ckpt)?)
            .map_err(|e| NetError::weights(&ckpt, format!("bad \"state\" metadata ({e})")))?;
        if &state.model != mcfg {
            return Err(NetError::weights(
                &ckpt,
                "the checkpoint's network shape differs from the requested one",
            ));
        }
        store::load_into(&varmap, &file.tensors, &ckpt)?;
        adam.load_state(&file.tensors)?;
    }

    let pads: Vec<f32> = data
        .train
        .iter()
        .map(|r| pad_value(r.mel_db.view()))
        .collect();
    let seq_len = sequence_frames(&net, cfg.sequence_windows);
    let center = mcfg.center_offset() as isize;
    let bands = mcfg.n_mels;
    let mut stopped_early = false;
    let mut epoch = state.next_epoch;
    while epoch < cfg.epochs {
        let mut rng = Rng::new(cfg.seed).fork(epoch as u64 + 1);
        net.dropout_rng().reseed(rng.next_u64());
        adam.config.learning_rate = cfg.learning_rate * cfg.lr_decay_per_epoch.powi(epoch as i32);
        // Sequences tile each recording from a random offset; frames outside it are masked.
        let n_seq = cfg.sequence_windows as isize;
        let mut seqs: Vec<(usize, isize)> = Vec::new();
        for (ri, r) in data.train.iter().enumerate() {
            let offset = (rng.next_u64() % cfg.sequence_windows as u64) as isize;
            let mut start = if offset > 0 { offset - n_seq } else { 0 };
            while start < r.mel_db.nrows() as isize {
                seqs.push((ri, start));
                start += n_seq;
            }
        }
        for i in (1..seqs.len()).rev() {
            let j = (rng.next_u64() % (i as u64 + 1)) as usize;
            seqs.swap(i, j);
        }
        let mut steps = seqs.len().div_ceil(cfg.batch_sequences);
        if let Some(cap) = cfg.max_steps_per_epoch {
            steps = steps.min(cap);
        }
        let mut loss_sum = 0.0f64;
        for (step, batch) in seqs.chunks(cfg.batch_sequences).take(steps).enumerate() {
            let b = batch.len();
            let mut buf = vec![0.0f32; b * seq_len * bands];
            for (k, &(ri, start)) in batch.iter().enumerate() {
                let r = &data.train[ri];
                let dst = &mut buf[k * seq_len * bands..][..seq_len * bands];
                copy_frames(r.mel_db.view(), start - center, seq_len, pads[ri], dst);
            }
            let x = Tensor::from_vec(buf, (b, seq_len, bands), &Device::Cpu)?;
            let logits = net.sequence_logits(&x, true)?;
            let (rows, windows, _) = logits.dims3()?;
            let mut targets = vec![0u32; rows * windows];
            let mut weights = vec![0.0f32; rows * windows];
            for row in 0..rows {
                for j in 0..windows {
                    let (k, s) = window_start(row, j, b);
                    let (ri, start) = batch[k];
                    let frame = start + s as isize;
                    if s < cfg.sequence_windows && frame >= 0 && (frame as usize) < labels[ri].len()
                    {
                        let y = labels[ri][frame as usize];
                        targets[row * windows + j] = u32::from(y);
                        weights[row * windows + j] = if y == 1 { positive_weight } else { 1.0 };
                    }
                }
            }
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
                val_f1: None,
                best_f1: state.best_f1.max(0.0),
            });
        }
        let epoch_loss = (loss_sum / steps.max(1) as f64) as f32;
        state.epoch_losses.push(epoch_loss);
        let (f1, _) = validation_f1(&net, &data.val, &Decoder::default())?;
        if f1 > state.best_f1 {
            state.best_f1 = f1;
            state.best_epoch = epoch;
            state.since_best = 0;
            BowChangeDetector::from_varmap(mcfg, &varmap, Decoder::default(), String::new())?
                .save(out)?;
        } else {
            state.since_best += 1;
        }
        progress(&TrainProgress {
            epoch,
            epochs: cfg.epochs,
            step: steps,
            steps,
            loss: epoch_loss,
            val_f1: Some(f1),
            best_f1: state.best_f1,
        });
        epoch += 1;
        state.next_epoch = epoch;
        save_checkpoint(&ckpt, &varmap, &adam, &state)?;
        if state.since_best >= cfg.patience {
            stopped_early = true;
            break;
        }
    }

    let mut best = BowChangeDetector::load(out)?;
    let (_, probs) = validation_f1(best.net(), &data.val, &Decoder::default())?;
    let (decoder, tuned) = tune_decoder(&probs, &data.val);
    let train_minutes = total as f64 / 30.0 / 60.0;
    let report = TrainReport {
        epochs_run: state.next_epoch,
        best_epoch: state.best_epoch,
        best_val_f1: state.best_f1,
        tuned_val_f1: tuned,
        decoder,
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
    best.set_decoder(decoder);
    best.set_training_info(info.to_string());
    best.save(out)?;
    Ok(report)
}

fn set_vars(varmap: &VarMap, values: &HashMap<String, Tensor>) -> Result<()> {
    let data = varmap
        .data()
        .lock()
        .map_err(|_| NetError::Config("variable store poisoned".into()))?;
    for (name, t) in values {
        if let Some(v) = data.get(name) {
            v.set(t)?;
        }
    }
    Ok(())
}

fn save_checkpoint(
    path: &Path,
    varmap: &VarMap,
    adam: &Adam,
    state: &CheckpointState,
) -> Result<()> {
    let mut tensors = store::var_tensors(varmap);
    tensors.extend(adam.state()?);
    let mut meta = HashMap::new();
    meta.insert(store::KEY_FORMAT.to_string(), CHECKPOINT_FORMAT.to_string());
    meta.insert(
        store::KEY_VERSION.to_string(),
        crate::detector::FORMAT_VERSION.to_string(),
    );
    meta.insert(
        "state".to_string(),
        serde_json::to_string(state).map_err(|e| NetError::Config(e.to_string()))?,
    );
    store::write_atomically(path, &store::encode(&tensors, meta)?)
}
