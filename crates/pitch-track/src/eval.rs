//! Scores with mir_eval's conventions (checked against mir_eval 0.8 on fixtures made by
//! `scripts/make_mir_eval_fixtures.py`).
//!
//! * Melody ([`melody_scores`], as `mir_eval.melody`): reference and estimate on the same
//!   time grid, frequencies in Hz, 0 (or NaN) = unvoiced, a negative estimate = an unvoiced
//!   frame with a pitch guess. Raw pitch accuracy counts reference-voiced frames whose
//!   estimate is within ±50 cents; voicing recall and false alarm compare voicing only.
//! * Events ([`match_events`], as `mir_eval.util.match_events`): a maximum one-to-one
//!   matching of reference and estimated times within a tolerance.
//! * Note onsets ([`onset_prf`], as `mir_eval.transcription.onset_precision_recall_f1`):
//!   precision, recall and F over onsets matched one-to-one within ±50 ms.

use serde::{Deserialize, Serialize};

use crate::error::{PitchError, Result};

/// Digits mir_eval rounds distances to before comparing them with a tolerance.
const DECIMALS: f64 = 1e7;

/// Precision, recall and F-measure.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Prf {
    /// Matched / estimated.
    pub precision: f64,
    /// Matched / reference.
    pub recall: f64,
    /// Harmonic mean of precision and recall (0 when both are 0).
    pub f_measure: f64,
}

impl Prf {
    /// Scores from a match count and the two list lengths (all 0 if either list is empty,
    /// as mir_eval).
    pub fn from_counts(matched: usize, n_reference: usize, n_estimated: usize) -> Prf {
        if n_reference == 0 || n_estimated == 0 {
            return Prf::default();
        }
        let precision = matched as f64 / n_estimated as f64;
        let recall = matched as f64 / n_reference as f64;
        Prf {
            precision,
            recall,
            f_measure: f_measure(precision, recall),
        }
    }
}

/// `2 p r / (p + r)`, 0 when `p + r = 0` (mir_eval's `util.f_measure` with β = 1).
pub fn f_measure(precision: f64, recall: f64) -> f64 {
    if precision + recall == 0.0 {
        0.0
    } else {
        2.0 * precision * recall / (precision + recall)
    }
}

/// A maximum one-to-one matching of `reference` and `estimated` event times (seconds)
/// within `window_s`, as `(reference index, estimated index)` pairs. Inputs need not be
/// sorted. Each list is swept in time order, every reference taking the earliest unmatched
/// estimate within its window: for one-dimensional windows of equal width this greedy
/// matching has maximum size, like mir_eval's bipartite matching.
///
/// ```
/// let m = pitch_track::eval::match_events(&[1.0, 2.0, 3.0], &[1.04, 2.2, 2.95, 3.02], 0.05);
/// assert_eq!(m, vec![(0, 0), (2, 2)]);
/// ```
pub fn match_events(reference: &[f64], estimated: &[f64], window_s: f64) -> Vec<(usize, usize)> {
    let order = |x: &[f64]| {
        let mut idx: Vec<usize> = (0..x.len()).filter(|&i| x[i].is_finite()).collect();
        idx.sort_by(|&a, &b| x[a].total_cmp(&x[b]));
        idx
    };
    let (ref_order, est_order) = (order(reference), order(estimated));
    let within = |r: f64, e: f64| ((r - e).abs() * DECIMALS).round() / DECIMALS <= window_s;
    let mut pairs = Vec::new();
    let mut first_free = 0;
    for &r in &ref_order {
        let rt = reference[r];
        while first_free < est_order.len()
            && estimated[est_order[first_free]] < rt
            && !within(rt, estimated[est_order[first_free]])
        {
            first_free += 1;
        }
        if first_free < est_order.len() && within(rt, estimated[est_order[first_free]]) {
            pairs.push((r, est_order[first_free]));
            first_free += 1;
        }
    }
    pairs
}

/// Onset precision, recall and F with a `tolerance_s` window (mir_eval uses 0.05 s).
///
/// ```
/// let s = pitch_track::eval::onset_prf(&[0.5, 1.0, 1.5], &[0.52, 1.2], 0.05);
/// assert_eq!((s.precision, s.recall), (0.5, 1.0 / 3.0));
/// ```
pub fn onset_prf(reference_s: &[f64], estimated_s: &[f64], tolerance_s: f64) -> Prf {
    let matched = match_events(reference_s, estimated_s, tolerance_s).len();
    Prf::from_counts(matched, reference_s.len(), estimated_s.len())
}

/// Frame-level melody scores.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct MelodyScores {
    /// Share of reference-voiced frames whose estimated pitch is within the tolerance.
    pub raw_pitch_accuracy: f64,
    /// Share of reference-voiced frames estimated voiced.
    pub voicing_recall: f64,
    /// Share of reference-unvoiced frames estimated voiced.
    pub voicing_false_alarm: f64,
    /// Share of all frames right: unvoiced where the reference is unvoiced, voiced and in
    /// tune where it is voiced.
    pub overall_accuracy: f64,
}

/// Melody scores of `estimated_hz` against `reference_hz` on the same grid, with a
/// `tolerance_cents` window (mir_eval uses 50). Errors when the lengths differ.
///
/// ```
/// let s = pitch_track::eval::melody_scores(&[440.0, 440.0, 0.0, 0.0], &[445.0, 0.0, 0.0, 300.0], 50.0)?;
/// assert_eq!((s.raw_pitch_accuracy, s.voicing_recall, s.voicing_false_alarm), (0.5, 0.5, 0.5));
/// # Ok::<(), pitch_track::PitchError>(())
/// ```
pub fn melody_scores(
    reference_hz: &[f32],
    estimated_hz: &[f32],
    tolerance_cents: f64,
) -> Result<MelodyScores> {
    if reference_hz.len() != estimated_hz.len() {
        return Err(PitchError::LengthMismatch {
            what: "reference vs estimated melody",
            left: reference_hz.len(),
            right: estimated_hz.len(),
        });
    }
    let cents = |f: f32| -> f64 {
        let f = if f.is_finite() {
            f64::from(f).abs()
        } else {
            0.0
        };
        if f > 0.0 {
            1200.0 * (f / 10.0).log2()
        } else {
            0.0
        }
    };
    let (mut ref_voiced, mut ref_unvoiced) = (0usize, 0usize);
    let (mut hits, mut recalled, mut false_alarms, mut overall) = (0usize, 0usize, 0usize, 0usize);
    for (&r, &e) in reference_hz.iter().zip(estimated_hz) {
        let rv = r.is_finite() && r > 0.0;
        let ev = e.is_finite() && e > 0.0;
        let (rc, ec) = (cents(r), cents(e));
        let in_tune = rc != 0.0 && ec != 0.0 && (rc - ec).abs() < tolerance_cents;
        if rv {
            ref_voiced += 1;
            hits += usize::from(in_tune);
            recalled += usize::from(ev);
            overall += usize::from(ev && in_tune);
        } else {
            ref_unvoiced += 1;
            false_alarms += usize::from(ev);
            overall += usize::from(!ev);
        }
    }
    let ratio = |a: usize, b: usize| if b == 0 { 0.0 } else { a as f64 / b as f64 };
    Ok(MelodyScores {
        raw_pitch_accuracy: ratio(hits, ref_voiced),
        voicing_recall: ratio(recalled, ref_voiced),
        voicing_false_alarm: ratio(false_alarms, ref_unvoiced),
        overall_accuracy: ratio(overall, reference_hz.len()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matching_is_maximal_where_nearest_first_is_not() {
        // Nearest-first would pair 1.0 with 1.04 and leave 1.08 unmatched.
        let m = match_events(&[1.0, 1.1], &[1.04], 0.05);
        assert_eq!(m.len(), 1);
        let m = match_events(&[1.0, 1.09], &[1.04, 1.13], 0.05);
        assert_eq!(m.len(), 2);
    }

    #[test]
    fn empty_lists_score_zero() {
        assert_eq!(onset_prf(&[], &[1.0], 0.05), Prf::default());
        assert_eq!(onset_prf(&[1.0], &[], 0.05), Prf::default());
        assert!(melody_scores(&[1.0], &[], 50.0).is_err());
    }
}
