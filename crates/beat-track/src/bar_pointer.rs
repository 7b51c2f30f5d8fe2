//! Beats, downbeats, metre and tempo from per-frame beat and downbeat activations with a
//! bar-pointer model, as madmom's `DBNDownBeatTrackingProcessor` (Böck, Krebs & Widmer
//! 2016): one hidden Markov model per bar length (by default 1, 2, 3 and 4 beats; compound
//! metres count dotted beats, so 6/8 is 2, 9/8 is 3, 12/8 is 4 and 3/8 is 1), each decoded
//! with Viterbi (the crate's `bar_state` module); the most likely bar length wins. The tempo may
//! change at every beat (exponential penalty, `transition_lambda`), so rubato and ritardandi
//! are followed while beats, downbeats and the metre stay consistent with each other.
//!
//! After decoding, beats far from any activation (silence, a long gap) are dropped
//! ([`BarPointerConfig::gate`]), and the **confidence** — the mean beat activation at all
//! the decoded beats, dropped or not — says how much the activation supports them: near 0 on silence or noise,
//! and then no beats are returned at all ([`BarPointerConfig::min_confidence`]); nor are
//! they when fewer than [`BarPointerConfig::min_beats`] remain (a lone note). A few beats
//! get a lower confidence than many ([`BarPointerConfig::full_confidence_beats`]).
//!
//! ```
//! use beat_track::bar_pointer::{decode, BarPointerConfig};
//! // 20 s at 30 fps, a beat every 15 frames (120 bpm), every third one a downbeat.
//! let (mut beat, mut down) = (vec![0.02f32; 600], vec![0.01f32; 600]);
//! for k in (0..600).step_by(15) {
//!     if (k / 15) % 3 == 0 { down[k] = 0.9 } else { beat[k] = 0.9 }
//! }
//! let out = decode(&beat, &down, &BarPointerConfig::default())?;
//! assert_eq!(out.beats_per_bar, 3);
//! assert!((out.tempo_bpm - 120.0).abs() < 3.0);
//! assert!(out.confidence > 0.8);
//! # Ok::<(), beat_track::BeatError>(())
//! ```

use serde::{Deserialize, Serialize};

pub use crate::bar_pointer_config::BarPointerConfig;
use crate::bar_state::{BarStateSpace, FrameObservation, PathFrame};
use crate::error::{BeatError, Result};

/// What the decoder found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BarPointerBeats {
    /// Beat times in seconds.
    pub beats_s: Vec<f64>,
    /// Downbeat times in seconds (a subset of the beats).
    pub downbeats_s: Vec<f64>,
    /// Beats per bar of the winning model.
    pub beats_per_bar: usize,
    /// Tempo at every beat (bpm), from the neighbouring beat intervals.
    pub tempo_bpm_per_beat: Vec<f64>,
    /// The median of `tempo_bpm_per_beat` (0 without beats).
    pub tempo_bpm: f64,
    /// Mean beat activation at every decoded beat (also the dropped ones), scaled down
    /// when fewer than [`BarPointerConfig::full_confidence_beats`] beats are returned,
    /// 0–1; 0 when no beats are returned.
    pub confidence: f32,
    /// Log-probability of the winning path per bar length tried, in the order of
    /// [`BarPointerConfig::beats_per_bar`].
    pub log_probability: Vec<f64>,
}

const EPS: f32 = 1e-7;

/// Decodes `beat` (P(beat, not downbeat)) and `downbeat` (P(downbeat)) activations, one
/// value per frame at `cfg.fps` (module docs). Empty activations give no beats; activations
/// of different lengths or outside 0–1 (NaN included) are refused.
pub fn decode(beat: &[f32], downbeat: &[f32], cfg: &BarPointerConfig) -> Result<BarPointerBeats> {
    decode_with_downbeat_evidence(beat, downbeat, &[], cfg)
}

/// [`decode`] with other evidence of where bars start: `evidence[t]` (one value per
/// activation frame, or empty for none) is a log-bonus for a downbeat at frame `t`, e.g.
/// where a new bow starts. The bar length is chosen without it (a bonus per downbeat would
/// favour the bar lengths with the most downbeats, so every bar length is scored without it,
/// see [`BarPointerConfig::selection_upsample`]); the chosen bar length is then decoded with
/// it, which moves the bars' phase (and may move beats). Evidence of another length, or not
/// finite, is refused.
///
/// ```
/// use beat_track::bar_pointer::{decode_with_downbeat_evidence, BarPointerConfig};
/// // 20 s at 120 bpm, every beat alike: the activation cannot tell where bars start.
/// let (mut beat, down) = (vec![0.02f32; 600], vec![0.2f32; 600]);
/// let mut bows = vec![0.0f32; 600];
/// for k in (0..600).step_by(15) {
///     beat[k] = 0.7;
///     if (k / 15) % 2 == 1 {
///         bows[k] = 2.0; // but a new bow starts on every second beat
///     }
/// }
/// let cfg = BarPointerConfig {
///     beats_per_bar: vec![2],
///     bar_length_prior_per_frame: vec![],
///     ..Default::default()
/// };
/// let out = decode_with_downbeat_evidence(&beat, &down, &bows, &cfg)?;
/// assert!(out.downbeats_s.iter().all(|t| ((t * 30.0).round() as usize / 15) % 2 == 1));
/// # Ok::<(), beat_track::BeatError>(())
/// ```
pub fn decode_with_downbeat_evidence(
    beat: &[f32],
    downbeat: &[f32],
    evidence: &[f32],
    cfg: &BarPointerConfig,
) -> Result<BarPointerBeats> {
    if !evidence.is_empty() && evidence.len() != beat.len() {
        return Err(BeatError::InvalidActivation(format!(
            "{} frames of downbeat evidence for {} frames of activation",
            evidence.len(),
            beat.len()
        )));
    }
    if evidence.iter().any(|v| !v.is_finite()) {
        return Err(BeatError::InvalidActivation(
            "downbeat evidence that is not finite".into(),
        ));
    }
    // No evidence anywhere (no bow change heard): decode as without it.
    let evidence = if evidence.iter().all(|&v| v == 0.0) {
        &[][..]
    } else {
        evidence
    };
    decode_checked(beat, downbeat, evidence, cfg)
}

/// [`decode_with_downbeat_evidence`] over every bar length of `cfg` at once, `evidence`
/// already checked (empty, or one finite value per frame).
fn decode_checked(
    beat: &[f32],
    downbeat: &[f32],
    evidence: &[f32],
    cfg: &BarPointerConfig,
) -> Result<BarPointerBeats> {
    cfg.check()?;
    if beat.len() != downbeat.len() {
        return Err(BeatError::InvalidActivation(format!(
            "{} beat and {} downbeat frames",
            beat.len(),
            downbeat.len()
        )));
    }
    if let Some(i) = beat
        .iter()
        .chain(downbeat)
        .position(|v| !(0.0..=1.0).contains(v))
    {
        return Err(BeatError::InvalidActivation(format!(
            "value {i} is not a probability in 0–1"
        )));
    }
    let empty = BarPointerBeats {
        beats_s: Vec::new(),
        downbeats_s: Vec::new(),
        beats_per_bar: cfg.beats_per_bar[0],
        tempo_bpm_per_beat: Vec::new(),
        tempo_bpm: 0.0,
        confidence: 0.0,
        log_probability: Vec::new(),
    };
    if beat.len() < 2 {
        return Ok(empty);
    }
    // The bar length: every one of `cfg.beats_per_bar` decoded at the selection rate,
    // without the evidence (a bonus per downbeat would favour the bar lengths with the
    // most downbeats).
    // The activations at the decoding rate, which is also the selection rate by default.
    let rate = cfg.upsample;
    let (beat_up, downbeat_up) = (interpolate(beat, rate), interpolate(downbeat, rate));
    let mut log_probability = Vec::new();
    let mut paths = Vec::new();
    let mut best = 0;
    if cfg.beats_per_bar.len() > 1 {
        let selection = cfg.selection_rate();
        let at = BarPointerConfig {
            upsample: selection,
            ..cfg.clone()
        };
        let obs = if selection == rate {
            observations(&beat_up, &downbeat_up, &[], cfg)
        } else {
            observations(
                &interpolate(beat, selection),
                &interpolate(downbeat, selection),
                &[],
                cfg,
            )
        };
        let intervals = at.intervals();
        let region = at.region(&intervals);
        // Decoded at the final rate without evidence, the chosen path is already final.
        let keep_paths = selection == rate && evidence.is_empty();
        for &n in &cfg.beats_per_bar {
            let (score, path) = BarStateSpace::new(n, &intervals, cfg.transition_lambda, &region)
                .viterbi(&obs, keep_paths);
            log_probability.push(score);
            paths.push(path);
        }
        let frames = obs.len() as f64;
        let with_prior = |k: usize| {
            log_probability[k]
                + cfg
                    .bar_length_prior_per_frame
                    .get(k)
                    .copied()
                    .unwrap_or(0.0)
                    * frames
        };
        best = (0..log_probability.len())
            .max_by(|&a, &b| with_prior(a).total_cmp(&with_prior(b)))
            .unwrap_or(0);
    }
    // The chosen bar length at the decoding rate, with the evidence.
    let (beat, downbeat) = (beat_up, downbeat_up);
    let path = match paths.get_mut(best).filter(|p| !p.is_empty()) {
        Some(path) => std::mem::take(path),
        None => {
            let obs = observations(&beat, &downbeat, &interpolate(evidence, rate), cfg);
            let intervals = cfg.intervals();
            let (score, path) = BarStateSpace::new(
                cfg.beats_per_bar[best],
                &intervals,
                cfg.transition_lambda,
                &cfg.region(&intervals),
            )
            .viterbi(&obs, true);
            if log_probability.is_empty() {
                log_probability.push(score);
            }
            path
        }
    };
    let at = BarPointerConfig {
        fps: cfg.fps * rate as f64,
        upsample: 1,
        ..cfg.clone()
    };
    let mut out = empty;
    out.beats_per_bar = cfg.beats_per_bar[best];
    out.log_probability = log_probability;
    let any: Vec<f32> = beat.iter().zip(&downbeat).map(|(b, d)| b + d).collect();
    Ok(finish(&path, &any, &at, out))
}

/// `v` linearly interpolated to `k` values per value (the last one held).
fn interpolate(v: &[f32], k: usize) -> Vec<f32> {
    if k <= 1 {
        return v.to_vec();
    }
    let mut out = Vec::with_capacity(v.len() * k);
    for (i, &a) in v.iter().enumerate() {
        let b = v.get(i + 1).copied().unwrap_or(a);
        out.extend((0..k).map(|j| a + (b - a) * j as f32 / k as f32));
    }
    out
}

/// The per-frame log-likelihoods of checked activations (`evidence` empty or one value
/// per frame).
fn observations(
    beat: &[f32],
    downbeat: &[f32],
    evidence: &[f32],
    cfg: &BarPointerConfig,
) -> Vec<FrameObservation> {
    let none_scale = 1.0 / (cfg.observation_lambda as f32 - 1.0).max(1.0);
    let floor = cfg.observation_floor.max(EPS);
    beat.iter()
        .zip(downbeat)
        .enumerate()
        .map(|(t, (&b, &d))| FrameObservation {
            none: ((1.0 - b - d).max(EPS) * none_scale).ln(),
            beat: b.max(floor).ln(),
            downbeat: d.max(floor).ln() + evidence.get(t).copied().unwrap_or(0.0),
        })
        .collect()
}

/// Beats of a decoded path, gated, refined to the activation peak and measured.
fn finish(
    path: &[PathFrame],
    any: &[f32],
    cfg: &BarPointerConfig,
    mut out: BarPointerBeats,
) -> BarPointerBeats {
    let n = any.len();
    let window = (cfg.gate_window_s * cfg.fps).round() as usize;
    // Frames within the window of an activation ≥ gate (prefix count of gate frames).
    let mut prefix = vec![0usize; n + 1];
    for (i, &a) in any.iter().enumerate() {
        prefix[i + 1] = prefix[i] + usize::from(a >= cfg.gate);
    }
    let supported = |t: usize| prefix[(t + window + 1).min(n)] > prefix[t.saturating_sub(window)];
    let mut beats: Vec<(f64, bool, usize, f32)> = Vec::new();
    let (mut support, mut decoded) = (0.0f32, 0usize);
    for (t, f) in path.iter().enumerate() {
        if !f.beat_starts {
            continue;
        }
        let lo = t.saturating_sub(1);
        let hi = (t + 1).min(n - 1);
        let k = (lo..=hi).fold(t, |m, i| if any[i] > any[m] { i } else { m });
        support += any[k];
        decoded += 1;
        if !supported(t) {
            continue;
        }
        let offset = if k > 0 && k + 1 < n {
            let (a, b, c) = (any[k - 1], any[k], any[k + 1]);
            let den = a - 2.0 * b + c;
            if den < -1e-6 {
                (0.5 * (a - c) / den).clamp(-0.5, 0.5)
            } else {
                0.0
            }
        } else {
            0.0
        };
        let time = (k as f64 + f64::from(offset)) / cfg.fps;
        beats.push((time, f.beat_of_bar == 0, f.interval, any[k]));
    }
    // Over every decoded beat, gated or not: a lone note in a minute of silence supports
    // one beat of dozens.
    let mean_support = support / decoded.max(1) as f32;
    // Beats on an activation of their own (the gate keeps its neighbours too).
    let heard = beats.iter().filter(|b| b.3 >= cfg.gate).count();
    if heard < cfg.min_beats || mean_support < cfg.min_confidence {
        return out;
    }
    let evidence = heard as f32 / cfg.full_confidence_beats.max(1) as f32;
    let confidence = mean_support * evidence.min(1.0);
    // Tempo from the neighbouring intervals that are not gaps (≤ 1.5 decoded periods).
    let tempo: Vec<f64> = (0..beats.len())
        .map(|i| {
            let period = beats[i].2 as f64 / cfg.fps;
            let near = |a: usize, b: usize| {
                let d = beats[b].0 - beats[a].0;
                (d > 0.0 && d <= 1.5 * period).then_some(d)
            };
            let ibis: Vec<f64> = [
                i.checked_sub(1).and_then(|p| near(p, i)),
                (i + 1 < beats.len()).then(|| near(i, i + 1)).flatten(),
            ]
            .into_iter()
            .flatten()
            .collect();
            let d = if ibis.is_empty() {
                period
            } else {
                ibis.iter().sum::<f64>() / ibis.len() as f64
            };
            60.0 / d
        })
        .collect();
    let mut sorted = tempo.clone();
    sorted.sort_by(f64::total_cmp);
    out.tempo_bpm = sorted[sorted.len() / 2];
    out.tempo_bpm_per_beat = tempo;
    out.confidence = confidence;
    out.downbeats_s = beats.iter().filter(|b| b.1).map(|b| b.0).collect();
    out.beats_s = beats.iter().map(|b| b.0).collect();
    out
}
