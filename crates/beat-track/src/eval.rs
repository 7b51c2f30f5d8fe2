//! Beat and downbeat scores with mir_eval's conventions (`mir_eval.beat.f_measure`: events
//! matched one-to-one within ±70 ms; 0 when either list is empty). mir_eval's `evaluate`
//! also drops beats before 5 s first ([`trim_beats`]); the F-measure itself does not.

pub use performance::{match_events, Prf};

/// mir_eval's beat tolerance in seconds.
pub const BEAT_TOLERANCE_S: f64 = 0.07;

/// F-measure (with precision and recall) of `estimated_s` against `reference_s` within
/// `tolerance_s` (use [`BEAT_TOLERANCE_S`]); works for beats and downbeats alike.
///
/// ```
/// let s = beat_track::eval::beat_prf(&[1.0, 1.5, 2.0, 2.5], &[1.02, 1.55, 2.1], 0.07);
/// assert_eq!((s.precision, s.recall), (2.0 / 3.0, 0.5));
/// ```
pub fn beat_prf(reference_s: &[f64], estimated_s: &[f64], tolerance_s: f64) -> Prf {
    performance::event_prf(reference_s, estimated_s, tolerance_s)
}

/// `mir_eval.beat.trim_beats`: the beats at or after `min_beat_time_s` (mir_eval uses 5 s).
pub fn trim_beats(beats_s: &[f64], min_beat_time_s: f64) -> Vec<f64> {
    beats_s
        .iter()
        .copied()
        .filter(|&b| b >= min_beat_time_s)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_lists_score_zero_and_trim_drops_early_beats() {
        assert_eq!(beat_prf(&[], &[1.0], BEAT_TOLERANCE_S).f_measure, 0.0);
        assert_eq!(trim_beats(&[1.0, 5.0, 6.0], 5.0), vec![5.0, 6.0]);
        assert_eq!(beat_prf(&[1.0], &[1.07], BEAT_TOLERANCE_S).f_measure, 1.0);
    }
}
