//! Beats, downbeats, metre and tempo from per-frame beat and downbeat activations with a
//! bar-pointer model, as madmom's `DBNDownBeatTrackingProcessor` (Böck, Krebs & Widmer
//! 2016): one hidden Markov model per bar length (by default 1, 2, 3 and 4 beats; compound
//! metres count dotted beats, so 6/8 is 2, 9/8 is 3, 12/8 is 4 and 3/8 is 1), each decoded
//! with Viterbi ([`crate::bar_state`]); the most likely bar length wins. The tempo may
//! change at every beat (exponential penalty, `transition_lambda`), so rubato and ritardandi
//! are followed while beats, downbeats and the metre stay consistent with each other.
//!
//! After decoding, beats far from any activation (silence, a long gap) are dropped
//! ([`BarPointerConfig::gate`]), and the **confidence** — the mean beat activation at all
//! the decoded beats, dropped or not — says how much the activation supports them: near 0 on silence or noise,
//! and then no beats are returned at all ([`BarPointerConfig::min_confidence`]).
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

use crate::bar_state::{BarStateSpace, FrameObservation, PathFrame};
use crate::error::{BeatError, Result};

/// Settings of the decoder.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct BarPointerConfig {
    /// Frames per second of the activations.
    pub fps: f64,
    /// Slowest tempo (beats per minute at the notated beat).
    pub min_bpm: f64,
    /// Fastest tempo.
    pub max_bpm: f64,
    /// The bar lengths (beats per bar) to try.
    pub beats_per_bar: Vec<usize>,
    /// The activations are linearly interpolated to this many times `fps` before decoding
    /// (1 = not at all): at 30 fps a beat at 180 bpm is 10 frames, so the tempo can only
    /// move in 10 % steps and every step pays the tempo-change penalty; a finer grid lets
    /// fast beats be followed.
    pub upsample: usize,
    /// At most this many tempi (beat intervals log-spaced over the range, as madmom's
    /// `num_tempi`); 0 = every whole number of (upsampled) frames in the range.
    pub max_tempi: usize,
    /// Tempo-change penalty at beat boundaries (madmom's `transition_lambda`).
    pub transition_lambda: f64,
    /// One beat in this many frames of a beat period observes a beat (madmom's
    /// `observation_lambda`).
    pub observation_lambda: f64,
    /// At most this many seconds of a beat observe a beat (0 = no limit): without a limit
    /// a slow beat's observing region is wider than an activation peak, which favours
    /// decoding twice the tempo.
    pub max_beat_region_s: f64,
    /// Beat and downbeat activations below this are read as this much (the "no beat"
    /// one is not floored): with a fixed-width observing region a beat in silence would
    /// otherwise cost so much that the slowest tempo wins across a long silent gap.
    pub observation_floor: f32,
    /// Beats with no frame of beat activation ≥ `gate` within `gate_window_s` are dropped.
    pub gate: f32,
    /// Half-width of the gate's window in seconds.
    pub gate_window_s: f64,
    /// Below this confidence no beats are returned.
    pub min_confidence: f32,
    /// Log-probability per decoded frame (at `fps · upsample`) added to each bar length's path (same order as
    /// `beats_per_bar`; empty = none) before the most likely bar length is taken: a prior
    /// over metres that grows with the recording, as the paths' own log-probabilities do.
    pub bar_length_prior_per_frame: Vec<f64>,
}

impl Default for BarPointerConfig {
    fn default() -> Self {
        Self {
            fps: 30.0,
            min_bpm: 38.0,
            max_bpm: 215.0,
            // Chosen on the corpus's validation split (violin-train's `tune_beats`
            // example, corpus-hook): against 30 fps with every interval, no region limit,
            // λ 60/6, beat F .775 → .820, tempo ±8 % .654 → .750, double tempo .125 → .038.
            upsample: 2,
            max_tempi: 40,
            beats_per_bar: vec![1, 2, 3, 4],
            // Chosen on the corpus's validation split with beat-net's activations
            // (violin-train's `tune_beats` example); madmom uses 100 and 16 at 100 fps.
            transition_lambda: 100.0,
            observation_lambda: 8.0,
            max_beat_region_s: 0.05,
            observation_floor: 0.003,
            gate: 0.1,
            gate_window_s: 1.5,
            min_confidence: 0.1,
            // Chosen with `bar_length_prior_per_frame` on the validation split
            // (violin-train's `tune_beats` example): metre .567 → .692, downbeat F
            // .597 → .626, beat F .786 → .785.
            bar_length_prior_per_frame: vec![0.0025, 0.0075, 0.0025, 0.0],
        }
    }
}

impl BarPointerConfig {
    /// The beat intervals (frames at the decoding rate, `fps · upsample`) of the tempo
    /// range: every whole number of frames, or `max_tempi` of them log-spaced.
    pub fn intervals(&self) -> Vec<usize> {
        let fps = self.fps * self.upsample.max(1) as f64;
        let lo = ((60.0 * fps / self.max_bpm).floor() as usize).max(1);
        let hi = ((60.0 * fps / self.min_bpm).ceil() as usize).max(lo);
        if self.max_tempi == 0 || self.max_tempi > hi - lo {
            return (lo..=hi).collect();
        }
        let (a, b) = ((lo as f64).ln(), (hi as f64).ln());
        let steps = self.max_tempi.max(2) - 1;
        let mut out: Vec<usize> = (0..=steps)
            .map(|k| (a + (b - a) * k as f64 / steps as f64).exp().round() as usize)
            .collect();
        out.dedup();
        out
    }

    /// Frames of a beat that observe a beat, per interval of `intervals`.
    fn region(&self, intervals: &[usize]) -> Vec<usize> {
        let cap = if self.max_beat_region_s > 0.0 {
            ((self.max_beat_region_s * self.fps * self.upsample as f64).round() as usize).max(1)
        } else {
            usize::MAX
        };
        intervals
            .iter()
            .map(|&i| {
                ((i as f64 / self.observation_lambda).round() as usize)
                    .clamp(1, i)
                    .min(cap)
            })
            .collect()
    }

    fn check(&self) -> Result<()> {
        let bad = |m: &str| Err(BeatError::InvalidConfig(format!("bar pointer: {m}")));
        if !(self.fps.is_finite() && self.fps > 0.0) {
            return bad("fps must be positive");
        }
        if !(self.min_bpm > 0.0 && self.max_bpm >= self.min_bpm && self.max_bpm.is_finite()) {
            return bad("need 0 < min_bpm ≤ max_bpm");
        }
        if self.upsample == 0 || self.upsample > 8 {
            return bad("upsample must be 1 to 8");
        }
        if self.intervals().len() > usize::from(u16::MAX) {
            return bad("the tempo range has too many beat intervals");
        }
        if self.beats_per_bar.is_empty() || self.beats_per_bar.iter().any(|&b| b == 0 || b > 12) {
            return bad("beats_per_bar must list bar lengths of 1 to 12 beats");
        }
        if !self.bar_length_prior_per_frame.is_empty()
            && (self.bar_length_prior_per_frame.len() != self.beats_per_bar.len()
                || self
                    .bar_length_prior_per_frame
                    .iter()
                    .any(|p| !p.is_finite()))
        {
            return bad("bar_length_prior_per_frame must give one finite value per bar length");
        }
        if !(self.transition_lambda >= 0.0 && self.observation_lambda >= 1.0) {
            return bad("transition_lambda must be ≥ 0 and observation_lambda ≥ 1");
        }
        if !(0.0..1.0).contains(&self.observation_floor) {
            return bad("observation_floor must be in 0–1");
        }
        if !(self.max_beat_region_s >= 0.0 && self.max_beat_region_s.is_finite()) {
            return bad("max_beat_region_s must be ≥ 0 (0 = no limit)");
        }
        Ok(())
    }
}

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
    /// Mean beat activation at every decoded beat (also the dropped ones), 0–1; 0 when
    /// no beats are returned.
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
    if cfg.upsample > 1 {
        let dec = BarPointerConfig {
            fps: cfg.fps * cfg.upsample as f64,
            upsample: 1,
            ..cfg.clone()
        };
        let (b, d) = (
            interpolate(beat, cfg.upsample),
            interpolate(downbeat, cfg.upsample),
        );
        return Ok(decode_at_rate(&b, &d, &dec, empty));
    }
    Ok(decode_at_rate(beat, downbeat, cfg, empty))
}

/// `v` linearly interpolated to `k` values per value (the last one held).
fn interpolate(v: &[f32], k: usize) -> Vec<f32> {
    let mut out = Vec::with_capacity(v.len() * k);
    for (i, &a) in v.iter().enumerate() {
        let b = v.get(i + 1).copied().unwrap_or(a);
        out.extend((0..k).map(|j| a + (b - a) * j as f32 / k as f32));
    }
    out
}

/// [`decode`] on checked activations at the decoding rate `cfg.fps` (`cfg.upsample` 1).
fn decode_at_rate(
    beat: &[f32],
    downbeat: &[f32],
    cfg: &BarPointerConfig,
    mut empty: BarPointerBeats,
) -> BarPointerBeats {
    let none_scale = 1.0 / (cfg.observation_lambda as f32 - 1.0).max(1.0);
    let floor = cfg.observation_floor.max(EPS);
    let obs: Vec<FrameObservation> = beat
        .iter()
        .zip(downbeat)
        .map(|(&b, &d)| FrameObservation {
            none: ((1.0 - b - d).max(EPS) * none_scale).ln(),
            beat: b.max(floor).ln(),
            downbeat: d.max(floor).ln(),
        })
        .collect();
    let intervals = cfg.intervals();
    let decoded: Vec<(f64, Vec<PathFrame>)> = cfg
        .beats_per_bar
        .iter()
        .map(|&n| {
            BarStateSpace::new(
                n,
                &intervals,
                cfg.transition_lambda,
                &cfg.region(&intervals),
            )
            .viterbi(&obs)
        })
        .collect();
    let log_probability: Vec<f64> = decoded.iter().map(|d| d.0).collect();
    let frames = beat.len() as f64;
    let with_prior = |k: usize| {
        log_probability[k]
            + cfg
                .bar_length_prior_per_frame
                .get(k)
                .copied()
                .unwrap_or(0.0)
                * frames
    };
    let best = (0..decoded.len())
        .max_by(|&a, &b| with_prior(a).total_cmp(&with_prior(b)))
        .unwrap_or(0);
    empty.beats_per_bar = cfg.beats_per_bar[best];
    empty.log_probability = log_probability;
    let any: Vec<f32> = beat.iter().zip(downbeat).map(|(b, d)| b + d).collect();
    finish(&decoded[best].1, &any, cfg, empty)
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
    let confidence = support / decoded.max(1) as f32;
    if beats.is_empty() || confidence < cfg.min_confidence {
        return out;
    }
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
