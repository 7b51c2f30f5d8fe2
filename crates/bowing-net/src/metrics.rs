//! Precision, recall and F1 of detected bow changes with a frame tolerance, summed over
//! recordings (micro average), plus the two checks the README reports: agreement with note
//! onsets, and false changes on slurred note changes.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// Matched / unmatched counts that add up over recordings.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counts {
    /// Predicted events matched to a reference event.
    pub true_positives: usize,
    /// Predicted events without a match.
    pub false_positives: usize,
    /// Reference events without a match.
    pub false_negatives: usize,
}

impl Counts {
    /// Adds one recording's counts.
    pub fn add(&mut self, m: &Counts) {
        self.true_positives += m.true_positives;
        self.false_positives += m.false_positives;
        self.false_negatives += m.false_negatives;
    }

    /// `tp / (tp + fp)` (1 when nothing was predicted).
    pub fn precision(&self) -> f64 {
        let d = self.true_positives + self.false_positives;
        if d == 0 {
            1.0
        } else {
            self.true_positives as f64 / d as f64
        }
    }

    /// `tp / (tp + fn)` (1 when there was nothing to find).
    pub fn recall(&self) -> f64 {
        let d = self.true_positives + self.false_negatives;
        if d == 0 {
            1.0
        } else {
            self.true_positives as f64 / d as f64
        }
    }

    /// Harmonic mean of precision and recall.
    ///
    /// ```
    /// let c = bowing_net::metrics::Counts { true_positives: 8, false_positives: 2, false_negatives: 2 };
    /// assert!((c.f1() - 0.8).abs() < 1e-12);
    /// ```
    pub fn f1(&self) -> f64 {
        let (p, r) = (self.precision(), self.recall());
        if p + r == 0.0 {
            0.0
        } else {
            2.0 * p * r / (p + r)
        }
    }
}

/// Matches `predicted` to `truth` (frame indices) one-to-one: a pair matches when the
/// frames differ by at most `tolerance`, as many pairs as possible
/// ([`performance::match_events`]).
///
/// ```
/// use bowing_net::metrics::match_events;
/// let m = match_events(&[10, 31, 70], &[12, 30, 50], 2);
/// assert_eq!((m.true_positives, m.false_positives, m.false_negatives), (2, 1, 1));
/// assert!((m.f1() - 2.0 / 3.0).abs() < 1e-12);
/// ```
pub fn match_events(predicted: &[usize], truth: &[usize], tolerance: usize) -> Counts {
    let sorted: Vec<usize>;
    let truth = if truth.is_sorted() {
        truth
    } else {
        sorted = {
            let mut v = truth.to_vec();
            v.sort_unstable();
            v
        };
        &sorted
    };
    let true_positives = matched_predictions(predicted, truth, tolerance)
        .iter()
        .filter(|&&m| m)
        .count();
    Counts {
        true_positives,
        false_positives: predicted.len() - true_positives,
        false_negatives: truth.len() - true_positives,
    }
}

/// Which predictions are matched to a reference event by the workspace's one matcher
/// ([`performance::match_events`]: a maximum one-to-one matching within `tolerance` frames).
pub fn matched_predictions(predicted: &[usize], truth: &[usize], tolerance: usize) -> Vec<bool> {
    let p: Vec<f64> = predicted.iter().map(|&v| v as f64).collect();
    let t: Vec<f64> = truth.iter().map(|&v| v as f64).collect();
    let mut used = vec![false; predicted.len()];
    for (_, i) in performance::match_events(&t, &p, tolerance as f64) {
        used[i] = true;
    }
    used
}

/// Accumulated figures for a set of recordings.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Scores {
    /// Recordings scored.
    pub recordings: usize,
    /// Their total length in minutes.
    pub minutes: f64,
    /// Bow changes, ±2 frames.
    pub changes_2: Counts,
    /// Bow changes, ±3 frames.
    pub changes_3: Counts,
    /// Predictions against note onsets, ±3 frames (empty when onsets are unknown).
    pub onsets_3: Counts,
    /// Note changes inside slurs (no bow change there).
    pub slurred_changes: usize,
    /// Slurred note changes with a false predicted change within ±3 frames.
    pub slurred_false_alarms: usize,
}

impl Scores {
    /// Adds one recording: `predicted` frames against its labels.
    pub fn add(
        &mut self,
        predicted: &[usize],
        changes: &[usize],
        onsets: &[usize],
        slurred: &[usize],
        frames: usize,
    ) {
        self.recordings += 1;
        self.minutes += frames as f64 / 30.0 / 60.0;
        self.changes_2.add(&match_events(predicted, changes, 2));
        self.changes_3.add(&match_events(predicted, changes, 3));
        if !onsets.is_empty() {
            self.onsets_3.add(&match_events(predicted, onsets, 3));
        }
        let matched = matched_predictions(predicted, changes, 3);
        let false_preds: Vec<usize> = predicted
            .iter()
            .zip(&matched)
            .filter(|(_, &m)| !m)
            .map(|(&p, _)| p)
            .collect();
        self.slurred_changes += slurred.len();
        self.slurred_false_alarms += slurred
            .iter()
            .filter(|&&s| false_preds.iter().any(|&p| p.abs_diff(s) <= 3))
            .count();
    }

    /// Share of slurred note changes left without a false change (1 = no false alarm).
    pub fn slur_precision(&self) -> f64 {
        if self.slurred_changes == 0 {
            1.0
        } else {
            1.0 - self.slurred_false_alarms as f64 / self.slurred_changes as f64
        }
    }
}

/// Scores over all recordings and per source group (`builtin`, `soundfont`, `urmp`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Evaluation {
    /// Everything.
    pub all: Scores,
    /// Per group.
    pub by_group: BTreeMap<String, Scores>,
}

/// Detects bow changes in every recording with `detector` and scores them.
pub fn evaluate(
    detector: &crate::BowChangeDetector,
    recordings: &[crate::data::Recording],
) -> crate::Result<Evaluation> {
    let mut eval = Evaluation::default();
    for r in recordings {
        let predicted = detector.detect_frames(r.mel_db.view())?;
        let frames = r.mel_db.nrows();
        eval.all
            .add(&predicted, &r.changes, &r.onsets, &r.slurred, frames);
        eval.by_group
            .entry(r.group.clone())
            .or_default()
            .add(&predicted, &r.changes, &r.onsets, &r.slurred, frames);
    }
    Ok(eval)
}

/// Validation F1 (±2 frames) of `net` with `decoder`, and the per-recording probabilities.
pub fn validation_f1(
    net: &crate::BowingNet,
    val: &[crate::data::Recording],
    decoder: &crate::Decoder,
) -> crate::Result<(f64, Vec<Vec<f32>>)> {
    let mut counts = Counts::default();
    let mut all = Vec::with_capacity(val.len());
    for r in val {
        let p = crate::infer::frame_probabilities(net, r.mel_db.view())?;
        counts.add(&match_events(&decoder.pick(&p), &r.changes, 2));
        all.push(p);
    }
    Ok((counts.f1(), all))
}

/// F1 (±2 frames, events pooled) of `decoder` over per-recording change probabilities
/// `probs` of the recordings `val`.
pub fn decoder_f1(
    probs: &[Vec<f32>],
    val: &[crate::data::Recording],
    decoder: &crate::Decoder,
) -> f64 {
    let mut c = Counts::default();
    for (p, r) in probs.iter().zip(val) {
        c.add(&match_events(&decoder.pick(p), &r.changes, 2));
    }
    c.f1()
}

/// The decoder (threshold 0.2–0.9, spacing 2–4 frames) with the best F1 at ±2 frames.
pub fn tune_decoder(probs: &[Vec<f32>], val: &[crate::data::Recording]) -> (crate::Decoder, f64) {
    let mut best = (crate::Decoder::default(), -1.0);
    for spacing in 2..=4 {
        for k in 0..=14 {
            let d = crate::Decoder {
                threshold: 0.2 + 0.05 * k as f32,
                min_spacing_frames: spacing,
                run_split: None,
            };
            let f1 = decoder_f1(probs, val, &d);
            if f1 > best.1 {
                best = (d, f1);
            }
        }
    }
    best
}

/// `base` with the [`crate::RunSplit`] (frames per change 2.5–4, offset −1 to 1 frame) that
/// scores the best F1 at ±2 frames, and that F1; `base` itself (and its F1) when no split
/// beats it.
pub fn tune_run_split(
    probs: &[Vec<f32>],
    val: &[crate::data::Recording],
    base: crate::Decoder,
) -> (crate::Decoder, f64) {
    let plain = crate::Decoder {
        run_split: None,
        ..base
    };
    let mut best = (plain, decoder_f1(probs, val, &plain));
    for frames_per_change in [2.5f32, 3.0, 3.5, 4.0] {
        for offset_frames in [-1.0f32, 0.0, 1.0] {
            let d = crate::Decoder {
                run_split: Some(crate::RunSplit {
                    frames_per_change,
                    offset_frames,
                }),
                ..base
            };
            let f1 = decoder_f1(probs, val, &d);
            if f1 > best.1 {
                best = (d, f1);
            }
        }
    }
    best
}
