//! Training (behind the `train` feature): random crops of the training recordings with
//! tempo augmentation ([`crate::batch`]), cross-entropy over no-beat/beat/downbeat with a
//! beat's neighbours at half weight, Adam with warm-up + cosine schedule, seeded
//! initialisation, crops and dropout; after every epoch the validation recordings are run
//! whole and the weights are kept when the validation score (mean of beat and downbeat F of
//! plain peak picking, ±70 ms) improves; early stopping after `patience` epochs without.
//! A share of the crops ([`TrainConfig::quiet_crop_prob`]) is silence or faint noise with no
//! beat ([`crate::batch::quiet_crop`]), so the network stays low where nothing is played.

use std::path::Path;
use std::time::Instant;

use candle_core::{Device, Tensor};
use net_core::frames::{random_eq_curve, shift_bands};
use net_core::rng::Rng;
use net_core::{set_band_statistics, vars, Adam, AdamConfig, LrSchedule, TrainState};
use serde::{Deserialize, Serialize};

use crate::activation::{probabilities, BeatActivation};
use crate::batch::{equalise, quiet_crop, random_crop, targets};
use crate::data::{Recording, Splits};
use crate::error::{BeatNetError, Result};
use crate::features::{EXTRA_FEATURES, FPS};
use crate::model::{BeatNet, Config, CLASSES};
use net_core::nn::weighted_cross_entropy;

/// Training settings (JSON: any subset; unknown fields are refused).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TrainConfig {
    /// The network's shape.
    pub model: Config,
    /// Maximum epochs; the schedule spans them.
    pub epochs: usize,
    /// Stop after this many epochs without a better validation score.
    pub patience: usize,
    /// Seed of initialisation, crops and dropout.
    pub seed: u64,
    /// Adam's peak learning rate.
    pub learning_rate: f64,
    /// How the learning rate moves over the steps.
    pub schedule: LrSchedule,
    /// Crops per step.
    pub batch_crops: usize,
    /// Frames per crop (after stretching).
    pub crop_frames: usize,
    /// Range of the time stretch (source frames per crop frame); `(1, 1)` = none.
    pub stretch: (f64, f64),
    /// Loss weight of the frames next to a beat (which carry the beat's class).
    pub neighbour_weight: f32,
    /// Steps per epoch; `None` = as many as cover the training frames once.
    pub steps_per_epoch: Option<usize>,
    /// Global gradient-norm clip.
    pub clip_norm: Option<f64>,
    /// Chance that a crop is a quiet one instead of a recording's ([`quiet_crop`]: silence
    /// or faint stationary noise, every frame "no beat"); 0 draws none and leaves the random
    /// stream as it was without the setting.
    pub quiet_crop_prob: f64,
    /// A recording's crop moves its mel bands by a whole number of bands drawn from
    /// −`band_shift`..=`band_shift` (edge bands repeated): a pitch shift of up to a few
    /// semitones, so the network hears the training works in other keys and registers; 0
    /// draws nothing and leaves the random stream as it was without the setting.
    pub band_shift: usize,
    /// A recording's crop is heard through a random equaliser up to about this deep (dB;
    /// [`net_core::frames::random_eq_curve`], applied by [`crate::batch::equalise`]), standing
    /// for violins and recording chains the corpus lacks; 0 draws nothing and leaves the
    /// random stream as it was without the setting.
    pub timbre_eq_db: f32,
    /// Free text stored with the weights (e.g. the data folder).
    pub data_description: String,
}

impl Default for TrainConfig {
    fn default() -> Self {
        Self {
            model: Config::default(),
            epochs: 20,
            patience: 5,
            seed: 1,
            learning_rate: 2e-3,
            schedule: LrSchedule::WarmupCosine {
                warmup_fraction: 0.03,
                final_fraction: 0.05,
            },
            batch_crops: 8,
            crop_frames: 750,
            stretch: (0.8, 1.25),
            neighbour_weight: 0.5,
            steps_per_epoch: None,
            clip_norm: Some(5.0),
            quiet_crop_prob: 0.0,
            band_shift: 0,
            timbre_eq_db: 0.0,
            data_description: String::new(),
        }
    }
}

/// What the progress callback is told.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainProgress {
    /// Epoch (0-based).
    pub epoch: usize,
    /// Steps done in this epoch.
    pub step: usize,
    /// Steps per epoch.
    pub steps: usize,
    /// Mean training loss of this epoch so far.
    pub loss: f32,
    /// Validation scores of the epoch just finished (`None` during the epoch).
    pub val: Option<ValidationScores>,
    /// Seconds since the run started.
    pub elapsed_s: f64,
}

/// Validation figures of one epoch.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ValidationScores {
    /// Mean cross-entropy per weighted frame.
    pub loss: f32,
    /// Beat F (±70 ms) of peak picking on `beat + downbeat`.
    pub beat_f: f64,
    /// Downbeat F (±70 ms) of peak picking on `downbeat`.
    pub downbeat_f: f64,
}

impl ValidationScores {
    /// The early-stopping score: the mean of the two F.
    pub fn score(&self) -> f64 {
        0.5 * (self.beat_f + self.downbeat_f)
    }
}

/// The result of [`train`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainReport {
    /// Epochs completed.
    pub epochs_run: usize,
    /// Epoch (0-based) of the kept weights.
    pub best_epoch: usize,
    /// Validation scores of the kept weights.
    pub best: Option<ValidationScores>,
    /// Mean training loss per epoch.
    pub epoch_losses: Vec<f32>,
    /// Training recordings and their minutes.
    pub train_recordings: usize,
    /// Minutes of training audio.
    pub train_minutes: f64,
    /// Wall time in seconds.
    pub wall_s: f64,
}

/// Local maxima of `p` at or above `threshold`, at least `min_gap` frames apart (the higher
/// wins), in seconds.
pub fn pick_peaks(p: &[f32], threshold: f32, min_gap: usize) -> Vec<f64> {
    let mut out: Vec<usize> = Vec::new();
    for t in 0..p.len() {
        let lo = t.saturating_sub(min_gap);
        let hi = (t + min_gap + 1).min(p.len());
        if p[t] >= threshold && p[lo..hi].iter().all(|&v| v <= p[t]) {
            if out.last().is_some_and(|&l| t - l <= min_gap) {
                continue;
            }
            out.push(t);
        }
    }
    out.into_iter().map(|t| t as f64 / FPS).collect()
}

fn f_measure(reference: &[f64], estimate: &[f64]) -> f64 {
    let mut used = vec![false; estimate.len()];
    let mut hits = 0usize;
    for &r in reference {
        if let Some((i, _)) = estimate
            .iter()
            .enumerate()
            .filter(|(i, e)| !used[*i] && (**e - r).abs() <= 0.07)
            .min_by(|a, b| (a.1 - r).abs().total_cmp(&(b.1 - r).abs()))
        {
            used[i] = true;
            hits += 1;
        }
    }
    if reference.is_empty() || estimate.is_empty() {
        return 0.0;
    }
    2.0 * hits as f64 / (reference.len() + estimate.len()) as f64
}

fn loss_of(net: &BeatNet, input: Tensor, t: &crate::batch::Targets, train: bool) -> Result<Tensor> {
    let n = t.classes.len();
    let logits = net.forward_t(&input, train)?.reshape((n, CLASSES))?;
    let classes = Tensor::from_vec(t.classes.clone(), n, &Device::Cpu)?;
    let weights = Tensor::from_vec(t.weights.clone(), n, &Device::Cpu)?;
    Ok(weighted_cross_entropy(&logits, &classes, &weights)?)
}

/// Validation scores of `net` on whole recordings.
pub fn validate(net: &BeatNet, recs: &[Recording]) -> Result<ValidationScores> {
    let (mut loss, mut beat_f, mut down_f) = (0.0f64, 0.0f64, 0.0f64);
    for rec in recs {
        let (frames, f) = rec.features.dim();
        let values: Vec<f32> = rec.features.iter().copied().collect();
        let input = Tensor::from_vec(values, (1, frames, f), &Device::Cpu)?;
        let logits = net.forward_t(&input, false)?;
        let t = targets(rec, 0.0, 1.0, frames, frames, 0.5);
        let classes = Tensor::from_vec(t.classes.clone(), frames, &Device::Cpu)?;
        let weights = Tensor::from_vec(t.weights.clone(), frames, &Device::Cpu)?;
        let l = weighted_cross_entropy(&logits.reshape((frames, CLASSES))?, &classes, &weights)?;
        loss += f64::from(l.to_scalar::<f32>()?);
        let act = probabilities(&logits)?;
        beat_f += f_measure(&rec.beats_s, &pick_peaks(&act.any_beat(), 0.3, 3));
        down_f += f_measure(&rec.downbeats_s, &pick_peaks(&act.downbeat, 0.3, 3));
    }
    let n = recs.len().max(1) as f64;
    Ok(ValidationScores {
        loss: (loss / n) as f32,
        beat_f: beat_f / n,
        downbeat_f: down_f / n,
    })
}

fn check(data: &Splits, cfg: &TrainConfig) -> Result<()> {
    cfg.model.validate()?;
    if data.train.is_empty() || data.val.is_empty() {
        return Err(BeatNetError::Input(
            "training needs train and validation recordings".into(),
        ));
    }
    let f = cfg.model.tcn.in_features;
    if let Some(r) = data
        .train
        .iter()
        .chain(&data.val)
        .find(|r| r.features.ncols() != f)
    {
        return Err(BeatNetError::Input(format!(
            "{} has {} features per frame, the network takes {f}",
            r.name,
            r.features.ncols()
        )));
    }
    let bad_lr = !cfg.learning_rate.is_finite() || cfg.learning_rate <= 0.0;
    let bad_stretch = !(cfg.stretch.0 > 0.0 && cfg.stretch.1 >= cfg.stretch.0);
    if cfg.epochs == 0 || cfg.batch_crops == 0 || cfg.crop_frames < 8 || bad_lr || bad_stretch {
        return Err(BeatNetError::Config(
            "epochs, batch_crops, the learning rate and the stretch must be positive, crops ≥ 8 frames".into(),
        ));
    }
    if !(0.0..=1.0).contains(&cfg.quiet_crop_prob) || f <= EXTRA_FEATURES {
        return Err(BeatNetError::Config(format!(
            "quiet_crop_prob must be in 0–1 (it is {}) and the network must take mel bands",
            cfg.quiet_crop_prob
        )));
    }
    if !(0.0..=60.0).contains(&cfg.timbre_eq_db) {
        return Err(BeatNetError::Config(format!(
            "timbre_eq_db must be in 0–60 dB (it is {})",
            cfg.timbre_eq_db
        )));
    }
    Ok(())
}

/// Trains a network on `data.train`, keeps the weights of the best validation epoch in
/// `out` (written whenever they improve) and returns the report.
pub fn train(
    data: &Splits,
    cfg: &TrainConfig,
    out: &Path,
    progress: &mut dyn FnMut(&TrainProgress),
) -> Result<TrainReport> {
    check(data, cfg)?;
    let clock = Instant::now();
    let (varmap, net) = BeatNet::seeded(&cfg.model, cfg.seed)?;
    set_band_statistics(
        &varmap,
        data.train.iter().map(|r| r.features.view()),
        cfg.model.tcn.in_features,
    )?;
    net.dropout_rng().reseed(cfg.seed ^ 0x5eed);
    let params = vars::trainable_vars(&varmap, |n| n.starts_with("norm."));
    let mut adam = Adam::new(
        params,
        AdamConfig {
            learning_rate: cfg.learning_rate,
            ..Default::default()
        },
    )?;
    let total_frames: usize = data.train.iter().map(Recording::frames).sum();
    let steps = cfg
        .steps_per_epoch
        .unwrap_or_else(|| total_frames.div_ceil(cfg.crop_frames * cfg.batch_crops))
        .max(1);
    // Recordings are drawn in proportion to their length.
    let lengths: Vec<f64> = data.train.iter().map(|r| r.frames() as f64).collect();
    let mut rng = Rng::new(cfg.seed);
    let mut state = TrainState::new(cfg.model.clone(), -1.0);
    let mut best = None;
    let f = cfg.model.tcn.in_features;
    for epoch in 0..cfg.epochs {
        let mut loss_sum = 0.0f64;
        for step in 0..steps {
            adam.config.learning_rate =
                cfg.schedule
                    .rate(cfg.learning_rate, epoch * steps + step, steps, cfg.epochs);
            let mut input = Vec::with_capacity(cfg.batch_crops * cfg.crop_frames * f);
            let mut classes = Vec::new();
            let mut weights = Vec::new();
            for _ in 0..cfg.batch_crops {
                let crop = if cfg.quiet_crop_prob > 0.0 && rng.chance(cfg.quiet_crop_prob) {
                    quiet_crop(cfg.crop_frames, f - EXTRA_FEATURES, &mut rng)?
                } else {
                    let i = rng.weighted(&lengths).unwrap_or(0);
                    let mut crop = random_crop(
                        &data.train[i],
                        cfg.crop_frames,
                        cfg.stretch,
                        cfg.neighbour_weight,
                        &mut rng,
                    );
                    if cfg.band_shift > 0 {
                        let k = cfg.band_shift as i64;
                        shift_bands(&mut crop.input, f, f - EXTRA_FEATURES, rng.int(-k, k));
                    }
                    if cfg.timbre_eq_db > 0.0 {
                        let bands = f - EXTRA_FEATURES;
                        let curve = random_eq_curve(&mut rng, bands, cfg.timbre_eq_db);
                        equalise(&mut crop.input, f, &curve);
                    }
                    crop
                };
                input.extend_from_slice(&crop.input);
                classes.extend(crop.targets.classes);
                weights.extend(crop.targets.weights);
            }
            let x = Tensor::from_vec(input, (cfg.batch_crops, cfg.crop_frames, f), &Device::Cpu)?;
            let t = crate::batch::Targets { classes, weights };
            let loss = loss_of(&net, x, &t, true)?;
            loss_sum += f64::from(loss.to_scalar::<f32>()?);
            let grads = loss.backward()?;
            adam.step_clipped(&grads, cfg.clip_norm)?;
            progress(&TrainProgress {
                epoch,
                step: step + 1,
                steps,
                loss: (loss_sum / (step + 1) as f64) as f32,
                val: None,
                elapsed_s: clock.elapsed().as_secs_f64(),
            });
        }
        let val = validate(&net, &data.val)?;
        let mean_loss = (loss_sum / steps as f64) as f32;
        if state.end_epoch(epoch, mean_loss, val.score()) {
            best = Some(val);
            let info = serde_json::json!({
                "config": cfg,
                "epoch": epoch,
                "validation": val,
                "train_recordings": data.train.len(),
            });
            BeatActivation::from_varmap(&cfg.model, &varmap, info.to_string())?.save(out)?;
        }
        progress(&TrainProgress {
            epoch,
            step: steps,
            steps,
            loss: mean_loss,
            val: Some(val),
            elapsed_s: clock.elapsed().as_secs_f64(),
        });
        if state.should_stop(cfg.patience) {
            break;
        }
    }
    Ok(TrainReport {
        epochs_run: state.next_epoch,
        best_epoch: state.best_epoch,
        best,
        epoch_losses: state.epoch_losses,
        train_recordings: data.train.len(),
        train_minutes: total_frames as f64 / FPS / 60.0,
        wall_s: clock.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peaks_and_f_measure() {
        let mut p = vec![0.0f32; 100];
        p[10] = 0.9;
        p[11] = 0.8;
        p[40] = 0.5;
        p[70] = 0.2;
        let peaks = pick_peaks(&p, 0.3, 3);
        assert_eq!(peaks, vec![10.0 / FPS, 40.0 / FPS]);
        assert_eq!(f_measure(&[10.0 / FPS, 40.0 / FPS], &peaks), 1.0);
        assert_eq!(f_measure(&[], &peaks), 0.0);
        assert!((f_measure(&[0.0, 10.0 / FPS], &peaks) - 0.5).abs() < 1e-9);
    }

    #[test]
    fn configs_without_quiet_crops_still_parse_and_bad_chances_are_refused() {
        let old: TrainConfig =
            serde_json::from_str(r#"{"epochs":35,"patience":8,"seed":1}"#).unwrap();
        assert_eq!(old.quiet_crop_prob, 0.0);
        let new: TrainConfig = serde_json::from_str(r#"{"quiet_crop_prob":0.08}"#).unwrap();
        assert_eq!(new.quiet_crop_prob, 0.08);
        let rec = Recording {
            name: "r".into(),
            features: ndarray::Array2::zeros((100, new.model.tcn.in_features)),
            beats_s: vec![1.0],
            downbeats_s: vec![],
        };
        let data = Splits {
            train: vec![rec.clone()],
            val: vec![rec],
        };
        assert!(check(&data, &new).is_ok());
        assert_eq!(new.timbre_eq_db, 0.0);
        let bad = TrainConfig {
            quiet_crop_prob: 1.5,
            ..new.clone()
        };
        assert!(matches!(check(&data, &bad), Err(BeatNetError::Config(_))));
        let bad_eq = TrainConfig {
            timbre_eq_db: f32::NAN,
            ..new
        };
        assert!(matches!(
            check(&data, &bad_eq),
            Err(BeatNetError::Config(_))
        ));
    }
}
