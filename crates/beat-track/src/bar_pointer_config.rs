//! The settings of [`crate::bar_pointer`]'s decoder and the tempo grid they imply.

use serde::{Deserialize, Serialize};

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
    /// The bar length is chosen by decoding every one of `beats_per_bar` (log-probabilities
    /// only) with the activations interpolated to this many times `fps`; 0 (the default)
    /// = `upsample`. Only the chosen one is then decoded, at `fps · upsample`, with the
    /// downbeat evidence if there is any. Choosing at the activations' own rate (1) takes
    /// about a third less time, but the bar-length prior, tuned at the decoding rate, then
    /// outweighs the smaller gaps between the bar lengths' log-probabilities: on corpus-hook
    /// metre rose on validation (0.654 → 0.673) and fell on the test sets (held-out both
    /// 0.596 → 0.462, in-distribution 0.885 → 0.846), and across a long silent gap a 4/4
    /// is read as 2/4 at half the tempo. Re-tuning the prior for it finds the same prior.
    pub selection_upsample: usize,
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
    /// Fewer beats than this on an activation of at least `gate` (the gate's window keeps
    /// beats near one too) and none are returned, nor a tempo: two beats cannot tell a
    /// tempo, and a lone note's onset is not a pulse.
    pub min_beats: usize,
    /// The confidence is the mean activation at the decoded beats scaled by the share of
    /// this many beats on an activation of at least `gate` (1 from this many on): a
    /// handful of beats is weak evidence however clear each one is.
    pub full_confidence_beats: usize,
    /// Log-probability per decoded frame (at `fps ·` [`Self::selection_rate`]) added to each
    /// bar length's path (same order as `beats_per_bar`; empty = none) before the most likely bar length
    /// is taken: a prior over metres that grows with the recording, as the paths' own
    /// log-probabilities do.
    pub bar_length_prior_per_frame: Vec<f64>,
}

impl Default for BarPointerConfig {
    fn default() -> Self {
        Self {
            fps: 30.0,
            min_bpm: 38.0,
            max_bpm: 215.0,
            // Chosen on the corpus's validation split (violin-train's `tune_beats`
            // example, corpus-hook; with `max_beat_region_s` and `observation_floor`):
            // against 30 fps with every interval, no region limit and λ 60/6, beat F .775 →
            // .815, tempo ±8 % .654 → .740, double tempo .125 → .038.
            upsample: 2,
            selection_upsample: 0,
            // 30 instead of the 40 chosen above, for speed (phased decoding of 180 s 74 →
            // 47 ms), by a rule written before the run (validation within 0.005 beat and
            // downbeat F, 0.010 metre and tempo): `evaluate --split val` beat F .869 →
            // .868, downbeat .757 → .761, metre .654 → .644, tempo .788 → .779.
            max_tempi: 30,
            beats_per_bar: vec![1, 2, 3, 4],
            // Chosen with the four above; madmom uses 100 and 16 at 100 fps.
            transition_lambda: 100.0,
            observation_lambda: 8.0,
            max_beat_region_s: 0.05,
            observation_floor: 0.003,
            gate: 0.1,
            gate_window_s: 1.5,
            min_confidence: 0.1,
            // Set from what they mean (a tempo needs two intervals; two bars of 4/4 are
            // enough to trust), not tuned; no validation or test figure moves with them.
            min_beats: 3,
            full_confidence_beats: 8,
            // Chosen for the shipped beat-net on the validation split (violin-train's
            // `tune_beats` example, corpus-hook): metre .606 → .654, downbeat F .675 →
            // .689, beat F .799 → .806. The first value sits at the search's edge, on a
            // plateau (a search to −0.06 scores the same): with this network one beat
            // per bar (3/8) is hardly ever the better reading on validation.
            bar_length_prior_per_frame: vec![-0.03, 0.01, 0.005, 0.0],
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
    pub(crate) fn region(&self, intervals: &[usize]) -> Vec<usize> {
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

    /// The interpolation factor at which the bar length is chosen (`selection_upsample`,
    /// or `upsample` where that is 0).
    pub fn selection_rate(&self) -> usize {
        if self.selection_upsample == 0 {
            self.upsample
        } else {
            self.selection_upsample
        }
    }

    pub(crate) fn check(&self) -> Result<()> {
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
        if self.selection_upsample > 8 {
            return bad("selection_upsample must be 0 to 8");
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
        if self.min_beats > 1000 || self.full_confidence_beats > 1000 {
            return bad("min_beats and full_confidence_beats must be at most 1000");
        }
        Ok(())
    }
}
