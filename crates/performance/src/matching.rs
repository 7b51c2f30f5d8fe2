//! Event matching with mir_eval's conventions (checked against mir_eval 0.8 on fixtures made
//! by `scripts/make_mir_eval_fixtures.py`): [`match_events`] (as
//! `mir_eval.util.match_events`, a maximum one-to-one matching within a tolerance) and the
//! precision/recall/F of matched events ([`event_prf`], as
//! `mir_eval.transcription.onset_precision_recall_f1` and `mir_eval.beat.f_measure`). The one
//! matcher of the workspace: note onsets, beats, downbeats and bow changes are all scored
//! with it.

use serde::{Deserialize, Serialize};

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
/// let m = performance::match_events(&[1.0, 2.0, 3.0], &[1.04, 2.2, 2.95, 3.02], 0.05);
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

/// Precision, recall and F of `estimated_s` against `reference_s`, events matched one-to-one
/// within `tolerance_s` ([`match_events`]): note onsets (mir_eval uses 0.05 s), beats and
/// downbeats (0.07 s), bow changes.
///
/// ```
/// let s = performance::event_prf(&[0.5, 1.0, 1.5], &[0.52, 1.2], 0.05);
/// assert_eq!((s.precision, s.recall), (0.5, 1.0 / 3.0));
/// ```
pub fn event_prf(reference_s: &[f64], estimated_s: &[f64], tolerance_s: f64) -> Prf {
    let matched = match_events(reference_s, estimated_s, tolerance_s).len();
    Prf::from_counts(matched, reference_s.len(), estimated_s.len())
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
        assert_eq!(event_prf(&[], &[1.0], 0.05), Prf::default());
        assert_eq!(event_prf(&[1.0], &[], 0.05), Prf::default());
    }
}
