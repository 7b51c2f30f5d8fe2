//! Event matching with a tolerance: precision, recall and F1 of detected events (bow
//! changes, onsets, beats) against reference events.

use serde::{Deserialize, Serialize};

/// The result of matching predicted events to reference events one-to-one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EventMatch {
    /// Predicted events matched to a reference event.
    pub true_positives: usize,
    /// Predicted events without a match.
    pub false_positives: usize,
    /// Reference events without a match.
    pub false_negatives: usize,
    /// `tp / predicted` (1 when nothing was predicted).
    pub precision: f64,
    /// `tp / reference` (1 when there is nothing to find).
    pub recall: f64,
    /// Harmonic mean of precision and recall (1 when both lists are empty, 0 when no match).
    pub f1: f64,
}

/// Matches `predicted` to `truth` (frame indices): a pair matches when the frames differ by
/// at most `tolerance`, each event used once, as many pairs as possible
/// ([`performance::match_events`]).
///
/// ```
/// use pose_preproc::metrics::match_events;
/// let m = match_events(&[10, 31, 70], &[12, 30, 50], 2);
/// assert_eq!((m.true_positives, m.false_positives, m.false_negatives), (2, 1, 1));
/// assert!((m.f1 - 2.0 / 3.0).abs() < 1e-12);
/// ```
pub fn match_events(predicted: &[usize], truth: &[usize], tolerance: usize) -> EventMatch {
    let p: Vec<f64> = predicted.iter().map(|&v| v as f64).collect();
    let t: Vec<f64> = truth.iter().map(|&v| v as f64).collect();
    match_events_s(&p, &t, tolerance as f64)
}

/// [`match_events`] for times (e.g. seconds) with a real tolerance (e.g. 0.05 s).
///
/// ```
/// let m = pose_preproc::metrics::match_events_s(&[0.51, 1.2], &[0.5, 1.0], 0.05);
/// assert_eq!(m.true_positives, 1);
/// ```
pub fn match_events_s(predicted: &[f64], truth: &[f64], tolerance: f64) -> EventMatch {
    // The workspace's one matcher: a maximum one-to-one matching (mir_eval's rule).
    let tp = performance::match_events(truth, predicted, tolerance).len();
    let precision = if predicted.is_empty() {
        1.0
    } else {
        tp as f64 / predicted.len() as f64
    };
    let recall = if truth.is_empty() {
        1.0
    } else {
        tp as f64 / truth.len() as f64
    };
    let f1 = if predicted.is_empty() && truth.is_empty() {
        1.0
    } else if tp == 0 {
        0.0
    } else {
        2.0 * precision * recall / (precision + recall)
    };
    EventMatch {
        true_positives: tp,
        false_positives: predicted.len() - tp,
        false_negatives: truth.len() - tp,
        precision,
        recall,
        f1,
    }
}

/// F1 of `predicted` against `truth` with a frame tolerance (see [`match_events`]).
///
/// ```
/// assert_eq!(pose_preproc::metrics::f1_with_tolerance(&[5, 20], &[6, 20], 2), 1.0);
/// ```
pub fn f1_with_tolerance(predicted: &[usize], truth: &[usize], tolerance: usize) -> f64 {
    match_events(predicted, truth, tolerance).f1
}

/// Bowing attacks read off a skeleton, the measure of Kao & Su (2020): frames where the right
/// wrist's velocity along its main axis of movement changes sign. The wrist track is
/// projected on the main axis of its 2-D scatter, smoothed (4th-order Butterworth, 5 Hz
/// low-pass, zero phase) and a reversal counts once the velocity passes 0.05 px/frame the
/// other way (so noise on a still wrist is not an attack); it is dated at the frame where
/// the velocity crossed zero. Motions shorter than 40 frames have none.
///
/// ```
/// use ndarray::Array3;
/// // The right wrist moves right for 30 frames, left for 30, right for 30.
/// let mut frames = Array3::<f32>::zeros((90, 10, 2));
/// for t in 0..90 {
///     let x = if t < 30 { t } else if t < 60 { 60 - t } else { t - 60 };
///     frames[[t, skeleton::Joint::RWrist.index(), 0]] = 10.0 * x as f32;
/// }
/// let m = skeleton::Motion::new(30.0, frames)?;
/// let attacks = pose_preproc::metrics::bowing_attack_frames(&m)?;
/// assert_eq!(attacks.len(), 2);
/// assert!(attacks.iter().zip([30, 60]).all(|(&a, b)| a.abs_diff(b) <= 2));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn bowing_attack_frames(motion: &skeleton::Motion) -> crate::Result<Vec<usize>> {
    use dsp_mel::filters::{filtfilt, Butterworth};
    let w = motion.joint(skeleton::Joint::RWrist);
    let n = w.nrows();
    if n < 40 {
        return Ok(Vec::new());
    }
    let mean = [
        w.column(0).mean().unwrap_or(0.0),
        w.column(1).mean().unwrap_or(0.0),
    ];
    let (mut sxx, mut sxy, mut syy) = (0f64, 0f64, 0f64);
    for r in w.rows() {
        let (x, y) = (f64::from(r[0] - mean[0]), f64::from(r[1] - mean[1]));
        sxx += x * x;
        sxy += x * y;
        syy += y * y;
    }
    // Main axis: eigenvector of the larger eigenvalue of the 2×2 covariance.
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let (ax, ay) = (angle.cos(), angle.sin());
    let projected: Vec<f64> = w
        .rows()
        .into_iter()
        .map(|r| f64::from(r[0]) * ax + f64::from(r[1]) * ay)
        .collect();
    let tf = Butterworth::lowpass(4, 5.0, motion.fps())?.transfer_function();
    let smooth = filtfilt(&tf.b, &tf.a, &projected)?;
    const DEADBAND_PX: f64 = 0.05;
    let mut out = Vec::new();
    let mut direction = 0.0f64;
    let mut crossing = 0usize;
    for (t, p) in smooth.windows(2).enumerate() {
        let v = p[1] - p[0];
        if v * direction <= 0.0 && crossing == 0 {
            crossing = t;
        }
        if v.abs() > DEADBAND_PX && v.signum() != direction {
            if direction != 0.0 {
                out.push(crossing);
            }
            direction = v.signum();
        }
        if v * direction > 0.0 {
            crossing = 0;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_to_one_and_closest_first() {
        // Two predictions near one truth: only one matches.
        let m = match_events(&[10, 11], &[10], 2);
        assert_eq!(
            (m.true_positives, m.false_positives, m.false_negatives),
            (1, 1, 0)
        );
        // Maximum matching: 9 takes 10 and 11 takes 12, rather than 11 → 10 alone.
        let m = match_events(&[9, 11], &[10, 12], 2);
        assert_eq!(m.true_positives, 2);
    }

    #[test]
    fn empty_lists() {
        assert_eq!(match_events(&[], &[], 2).f1, 1.0);
        let m = match_events(&[], &[4], 2);
        assert_eq!((m.precision, m.recall, m.f1), (1.0, 0.0, 0.0));
        assert_eq!(match_events(&[4], &[], 2).f1, 0.0);
        assert_eq!(match_events(&[4], &[7], 2).f1, 0.0);
    }
}
