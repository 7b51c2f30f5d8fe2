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

pub use performance::{f_measure, match_events, Prf};
use serde::{Deserialize, Serialize};

use crate::error::{PitchError, Result};

/// Onset precision, recall and F with a `tolerance_s` window (mir_eval uses 0.05 s): the
/// workspace's one event matcher, [`performance::event_prf`].
///
/// ```
/// let s = pitch_track::eval::onset_prf(&[0.5, 1.0, 1.5], &[0.52, 1.2], 0.05);
/// assert_eq!((s.precision, s.recall), (0.5, 1.0 / 3.0));
/// ```
pub fn onset_prf(reference_s: &[f64], estimated_s: &[f64], tolerance_s: f64) -> Prf {
    performance::event_prf(reference_s, estimated_s, tolerance_s)
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
    fn melody_lengths_must_agree() {
        assert!(melody_scores(&[1.0], &[], 50.0).is_err());
    }
}
