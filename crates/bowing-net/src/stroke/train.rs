//! Training the stroke network (feature `train`): random crops of the training recordings,
//! three losses on one trunk, validation after every epoch.
//!
//! * **Bow change**: binary cross-entropy per frame; the frame of a change and its two
//!   neighbours are positive (the neighbours at half weight, absorbing ±1-frame jitter) and
//!   positives weigh `change_positive_weight`.
//! * **Direction**: binary cross-entropy (down = 1) on the frames inside a labelled stroke.
//!   Its output is decoded with the bowing rules ([`super::direction`]) when the weights
//!   carry a direction decoder; the shipped ones do not (it did not beat the rules on
//!   validation data).
//! * **String**: cross-entropy over G, D, A, E on the frames with a sounding note.
//! * Adam with warm-up and cosine decay ([`LrSchedule`]); seeded initialisation, crops and
//!   dropout, so a run is reproducible bit for bit.
//! * After each epoch the bow-change decoder is tuned on the validation recordings only
//!   (threshold and spacing, [`crate::metrics::tune_decoder`]); the epoch with the best
//!   validation score (change F1 + string accuracy) is kept and written to the output
//!   file.

use std::path::Path;
use std::time::Instant;

use candle_core::{Device, Tensor, D};
use candle_nn::{VarBuilder, VarMap};
use ndarray::Array2;
use net_core::nn::DropoutRng;
use net_core::rng::Rng;
use net_core::{vars, Adam, AdamConfig, LrSchedule, TrainState};
use serde::{Deserialize, Serialize};

use super::metrics::{score_recordings, StrokeScores};
use super::model::{StrokeConfig, StrokeNet, DTYPE};
use super::{stroke_input, StrokeDetector};
use crate::data::{Recording, Splits};
use crate::decode::Decoder;
use crate::error::{NetError, Result};
use crate::features::frame_of;

/// Training settings (JSON: any subset of the fields).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StrokeTrainConfig {
    /// The network's shape.
    pub model: StrokeConfig,
    /// Epochs; an epoch draws as many crop frames as the training set has frames.
    pub epochs: usize,
    /// Stop after this many epochs without a better validation score.
    pub patience: usize,
    /// Crops per step.
    pub batch_crops: usize,
    /// Frames per crop (512 ≈ 17 s).
    pub crop_frames: usize,
    /// Adam's peak learning rate.
    pub learning_rate: f64,
    /// Weight of a positive bow-change frame.
    pub change_positive_weight: f32,
    /// Weight of the direction loss.
    pub direction_weight: f32,
    /// Weight of the string loss.
    pub string_weight: f32,
    /// Seed of initialisation, crops and dropout.
    pub seed: u64,
    /// Cap on steps per epoch (for quick runs); `None` = a full epoch.
    pub max_steps_per_epoch: Option<usize>,
    /// Start from these weights (a stroke-network safetensors file, same shape) instead of
    /// a seeded initialisation: training then continues them (fine-tuning), with the
    /// normalisation statistics stored in that file.
    pub init_from: Option<std::path::PathBuf>,
    /// Depth (dB) of the random equaliser each crop is heard through
    /// ([`super::timbre`]); 0 = none.
    pub timbre_eq_db: f32,
}

impl Default for StrokeTrainConfig {
    fn default() -> Self {
        Self {
            model: StrokeConfig::default(),
            epochs: 20,
            patience: 5,
            batch_crops: 16,
            crop_frames: 512,
            learning_rate: 2e-3,
            change_positive_weight: 4.0,
            direction_weight: 0.5,
            string_weight: 0.5,
            seed: 1,
            max_steps_per_epoch: None,
            init_from: None,
            timbre_eq_db: 0.0,
        }
    }
}

/// One line of progress.
#[derive(Debug, Clone, PartialEq)]
pub struct StrokeProgress {
    /// Epoch (0-based).
    pub epoch: usize,
    /// Step within the epoch (1-based) and steps in it.
    pub step: usize,
    /// Steps in the epoch.
    pub steps: usize,
    /// Mean loss so far in the epoch.
    pub loss: f32,
    /// Validation scores, after the epoch's last step.
    pub val: Option<StrokeScores>,
    /// Seconds since training started.
    pub elapsed_s: f64,
}

/// What training achieved.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StrokeTrainReport {
    /// The kept epoch.
    pub best_epoch: usize,
    /// Its validation scores.
    pub best_val: StrokeScores,
    /// The decoder tuned on validation data for it.
    pub decoder: Decoder,
    /// Epochs run.
    pub epochs_run: usize,
    /// Wall time, seconds.
    pub elapsed_s: f64,
}

struct Targets {
    change: Vec<f32>,
    change_w: Vec<f32>,
    down: Vec<f32>,
    down_w: Vec<f32>,
    string: Vec<u32>,
    string_w: Vec<f32>,
}

fn targets(r: &Recording, frames: usize, positive: f32) -> Targets {
    let mut t = Targets {
        change: vec![0.0; frames],
        change_w: vec![1.0; frames],
        down: vec![0.0; frames],
        down_w: vec![0.0; frames],
        string: vec![0; frames],
        string_w: vec![0.0; frames],
    };
    for &c in &r.changes {
        for (f, w) in [(c.wrapping_sub(1), 0.5), (c + 1, 0.5), (c, 1.0)] {
            if f < frames {
                t.change[f] = 1.0;
                t.change_w[f] = positive * w;
            }
        }
    }
    for s in &r.strokes {
        let down = f32::from(u8::from(s.direction == performance::BowDirection::Down));
        for f in frame_of(s.start_s)..frame_of(s.end_s).min(frames) {
            t.down[f] = down;
            t.down_w[f] = 1.0;
        }
    }
    for (f, &s) in r.strings.iter().enumerate().take(frames) {
        if (1..=4).contains(&s) {
            t.string[f] = u32::from(s - 1);
            t.string_w[f] = 1.0;
        }
    }
    t
}

/// Σ w·BCE(logit, y) / Σ w, stable for large logits.
fn weighted_bce(logits: &Tensor, y: &Tensor, w: &Tensor) -> candle_core::Result<Tensor> {
    let softplus_neg_abs = (logits.abs()?.neg()?.exp()? + 1.0)?.log()?;
    let per = ((logits.relu()? - (logits * y)?)? + softplus_neg_abs)?;
    let total = w.sum_all()?.to_scalar::<f32>()?.max(1e-6);
    (per * w)?.sum_all()? / f64::from(total)
}

/// Trains on `data.train`, validates on `data.val`, writes the best weights to `out`.
pub fn train_strokes(
    data: &Splits,
    cfg: &StrokeTrainConfig,
    out: &Path,
    progress: &mut dyn FnMut(&StrokeProgress),
) -> Result<StrokeTrainReport> {
    let started = Instant::now();
    cfg.model.validate()?;
    if data.train.is_empty() || data.val.is_empty() {
        return Err(NetError::Input(
            "training needs training and validation recordings".into(),
        ));
    }
    if cfg.crop_frames == 0 || cfg.batch_crops == 0 || cfg.epochs == 0 {
        return Err(NetError::Config(
            "epochs, batch_crops and crop_frames must be positive".into(),
        ));
    }
    for r in data.train.iter().chain(&data.val) {
        net_core::frames::check_mel(r.mel_db.view(), cfg.model.n_mels)
            .map_err(|e| NetError::Input(format!("{}: {}", r.name, e.0)))?;
    }
    let inputs: Vec<Array2<f32>> = data
        .train
        .iter()
        .map(|r| stroke_input(r.mel_db.view()))
        .collect();
    let labels: Vec<Targets> = data
        .train
        .iter()
        .zip(&inputs)
        .map(|(r, x)| targets(r, x.nrows(), cfg.change_positive_weight))
        .collect();
    let features = cfg.model.trunk.in_features;

    let varmap = VarMap::new();
    let dropout = DropoutRng::new(cfg.seed ^ 0x5eed);
    let net = StrokeNet::new(
        &cfg.model,
        VarBuilder::from_varmap(&varmap, DTYPE, &Device::Cpu),
        dropout.clone(),
    )?;
    vars::init_seeded(&varmap, cfg.seed, |name, dims| {
        (name.ends_with("weight") && !name.starts_with("norm.")).then(|| vars::glorot_bound(dims))
    })?;
    net_core::set_band_statistics(&varmap, inputs.iter().map(|x| x.view()), features)?;
    if let Some(init) = &cfg.init_from {
        let start = StrokeDetector::load(init)?;
        let mut target = varmap.clone();
        for (name, tensor) in start.named_tensors() {
            target.set_one(name, tensor).map_err(|e| {
                NetError::Input(format!(
                    "{}: cannot start from tensor {name} ({e})",
                    init.display()
                ))
            })?;
        }
    }
    let params = vars::trainable_vars(&varmap, |n| n.starts_with("norm."));
    let mut adam = Adam::new(
        params,
        AdamConfig {
            learning_rate: cfg.learning_rate,
            ..AdamConfig::default()
        },
    )?;
    let schedule = LrSchedule::WarmupCosine {
        warmup_fraction: 0.05,
        final_fraction: 0.02,
    };
    let total_frames: usize = inputs.iter().map(|x| x.nrows()).sum();
    let mut steps = total_frames
        .div_ceil(cfg.batch_crops * cfg.crop_frames)
        .max(1);
    if let Some(cap) = cfg.max_steps_per_epoch {
        steps = steps.min(cap.max(1));
    }
    let cumulative: Vec<f64> = inputs.iter().map(|x| x.nrows() as f64).collect();
    let mut state = TrainState::new(cfg.model.clone(), -1.0);
    let mut best: Option<(usize, StrokeScores, Decoder)> = None;
    let mut epochs_run = 0;
    for epoch in 0..cfg.epochs {
        let mut rng = Rng::new(cfg.seed).fork(epoch as u64 + 1);
        dropout.reseed(rng.next_u64());
        let mut loss_sum = 0.0f64;
        for step in 0..steps {
            adam.config.learning_rate =
                schedule.rate(cfg.learning_rate, epoch * steps + step, steps, cfg.epochs);
            let n = cfg.batch_crops * cfg.crop_frames;
            let mut x = vec![0.0f32; n * features];
            let mut y = Targets {
                change: vec![0.0; n],
                change_w: vec![0.0; n],
                down: vec![0.0; n],
                down_w: vec![0.0; n],
                string: vec![0; n],
                string_w: vec![0.0; n],
            };
            for b in 0..cfg.batch_crops {
                let ri = rng.weighted(&cumulative).unwrap_or(0);
                let len = inputs[ri].nrows();
                let start = if len > cfg.crop_frames {
                    rng.int(0, (len - cfg.crop_frames) as i64) as usize
                } else {
                    0
                };
                let take = (len - start).min(cfg.crop_frames);
                let o = b * cfg.crop_frames;
                let src = inputs[ri].slice(ndarray::s![start..start + take, ..]);
                for (k, row) in src.rows().into_iter().enumerate() {
                    for (j, v) in row.iter().enumerate() {
                        x[(o + k) * features + j] = *v;
                    }
                }
                let l = &labels[ri];
                let r = start..start + take;
                y.change[o..o + take].copy_from_slice(&l.change[r.clone()]);
                y.change_w[o..o + take].copy_from_slice(&l.change_w[r.clone()]);
                y.down[o..o + take].copy_from_slice(&l.down[r.clone()]);
                y.down_w[o..o + take].copy_from_slice(&l.down_w[r.clone()]);
                y.string[o..o + take].copy_from_slice(&l.string[r.clone()]);
                y.string_w[o..o + take].copy_from_slice(&l.string_w[r]);
                if cfg.timbre_eq_db > 0.0 {
                    let curve =
                        net_core::frames::random_eq_curve(&mut rng, features - 2, cfg.timbre_eq_db);
                    let crop = &mut x[o * features..(o + take) * features];
                    super::timbre::equalise(crop, features, &curve);
                }
                // A short recording's crop is padded with silence of weight 0.
                for k in take..cfg.crop_frames {
                    let row = &mut x[(o + k) * features..(o + k + 1) * features];
                    row.fill(super::FLOOR_DB);
                    row[features - 2] = 0.0;
                }
            }
            let shape = (cfg.batch_crops, cfg.crop_frames);
            let xt = Tensor::from_vec(
                x,
                (cfg.batch_crops, cfg.crop_frames, features),
                &Device::Cpu,
            )?;
            let t = |v: Vec<f32>| Tensor::from_vec(v, shape, &Device::Cpu);
            let logits = net.forward_t(&xt, true)?;
            let change = weighted_bce(&logits.change, &t(y.change)?, &t(y.change_w)?)?;
            let down = weighted_bce(&logits.down, &t(y.down)?, &t(y.down_w)?)?;
            let log_p = candle_nn::ops::log_softmax(&logits.string, D::Minus1)?;
            let cls = Tensor::from_vec(
                y.string,
                (cfg.batch_crops, cfg.crop_frames, 1),
                &Device::Cpu,
            )?;
            let picked = log_p.gather(&cls, D::Minus1)?.squeeze(D::Minus1)?;
            let sw = t(y.string_w)?;
            let s_total = sw.sum_all()?.to_scalar::<f32>()?.max(1e-6);
            let string = ((picked * sw)?.sum_all()? * (-1.0 / f64::from(s_total)))?;
            let loss = ((change + (down * f64::from(cfg.direction_weight))?)?
                + (string * f64::from(cfg.string_weight))?)?;
            let value = loss.to_scalar::<f32>()?;
            if !value.is_finite() {
                return Err(NetError::Input(format!(
                    "training diverged (loss {value}) at epoch {epoch}; lower the learning rate"
                )));
            }
            adam.backward_step(&loss)?;
            loss_sum += f64::from(value);
            progress(&StrokeProgress {
                epoch,
                step: step + 1,
                steps,
                loss: (loss_sum / (step + 1) as f64) as f32,
                val: None,
                elapsed_s: started.elapsed().as_secs_f64(),
            });
        }
        epochs_run = epoch + 1;
        let mut detector =
            StrokeDetector::from_varmap(&cfg.model, &varmap, Decoder::default(), String::new())?;
        let (scores, decoder) = score_recordings(&detector, &data.val, None)?;
        let mean_loss = (loss_sum / steps as f64) as f32;
        progress(&StrokeProgress {
            epoch,
            step: steps,
            steps,
            loss: mean_loss,
            val: Some(scores.clone()),
            elapsed_s: started.elapsed().as_secs_f64(),
        });
        if state.end_epoch(epoch, mean_loss, scores.selection_score()) {
            detector.set_decoder(decoder);
            detector.set_training_info(
                serde_json::json!({
                    "epoch": epoch,
                    "val": &scores,
                    "train_recordings": data.train.len(),
                    "train_frames": total_frames,
                    "config": cfg,
                })
                .to_string(),
            );
            detector.save(out)?;
            best = Some((epoch, scores, decoder));
        }
        if state.should_stop(cfg.patience) {
            break;
        }
    }
    let (best_epoch, best_val, decoder) =
        best.ok_or_else(|| NetError::Input("no epoch finished".into()))?;
    Ok(StrokeTrainReport {
        best_epoch,
        best_val,
        decoder,
        epochs_run,
        elapsed_s: started.elapsed().as_secs_f64(),
    })
}
