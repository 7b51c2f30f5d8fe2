//! Bow-change labels from the right wrist's vertical track (SPEC §3), the training target of
//! the bowing network.
//!
//! 1. low-pass the right-wrist y with a Butterworth filter (order 4, 5 Hz at the motion's fps),
//!    zero-phase (`filtfilt`, scipy-equal), so labels are not delayed;
//! 2. velocity `v[t] = y[t+1] − y[t]`;
//! 3. median filter of the velocity (window 15, edges repeat the end values);
//! 4. frame `t` is a detection when the mean velocity of the 10 frames before it
//!    (`v[t−10..t]`) and of the 10 frames after it (`v[t..t+10]`) both exceed the threshold
//!    (1 px/frame by default, in pixels of the source video) in magnitude and have opposite
//!    signs;
//! 5. each run of consecutive detections becomes one change frame: by default the frame in
//!    the run where the low-passed y turns ([`ChangePoint::Extremum`]), or the run's centre
//!    ([`ChangePoint::RunCentre`], SPEC's wording).
//!
//! Centring a motion does not change velocities, so labels are the same on centred and
//! uncentred tracks.

use dsp_mel::filters::{filtfilt, median_filter, Butterworth, EdgeMode};
use skeleton::{Joint, Motion};

use crate::config::{ChangePoint, LabelConfig};
use crate::error::{PosePreprocError, Result};

/// Fewest frames a clip needs for labels with `cfg`: the zero-phase filter pads
/// `3 · (order + 1)` frames at each end and needs more frames than that.
///
/// ```
/// assert_eq!(pose_preproc::labels::min_label_frames(&Default::default()), 16);
/// ```
pub fn min_label_frames(cfg: &LabelConfig) -> usize {
    3 * (cfg.lowpass_order + 1) + 1
}

/// Step 1: the zero-phase Butterworth low-pass of `y` sampled at `fps`.
pub fn lowpass(y: &[f64], fps: f64, cfg: &LabelConfig) -> Result<Vec<f64>> {
    cfg.validate()?;
    if y.len() < min_label_frames(cfg) {
        return Err(PosePreprocError::ClipTooShort {
            frames: y.len(),
            needed: min_label_frames(cfg),
        });
    }
    if let Some(frame) = y.iter().position(|v| !v.is_finite()) {
        return Err(PosePreprocError::NonFinite { frame });
    }
    let tf =
        Butterworth::lowpass(cfg.lowpass_order, cfg.lowpass_cutoff_hz, fps)?.transfer_function();
    Ok(filtfilt(&tf.b, &tf.a, y)?)
}

/// Steps 2–3: velocity of the filtered track (length `len − 1`), median-filtered.
pub fn smoothed_velocity(filtered: &[f64], cfg: &LabelConfig) -> Result<Vec<f64>> {
    let velocity: Vec<f64> = filtered.windows(2).map(|w| w[1] - w[0]).collect();
    Ok(median_filter(
        &velocity,
        cfg.velocity_median_window,
        EdgeMode::Nearest,
    )?)
}

/// Step 4: the runs `(first, last)` (inclusive frame indices) of detected frames, given the
/// smoothed velocity.
pub fn detection_runs(velocity: &[f64], cfg: &LabelConfig) -> Vec<(usize, usize)> {
    let ctx = cfg.context_frames;
    let n = velocity.len();
    let mut runs: Vec<(usize, usize)> = Vec::new();
    if n < 2 * ctx {
        return runs;
    }
    let mut prefix = Vec::with_capacity(n + 1);
    prefix.push(0.0f64);
    for v in velocity {
        prefix.push(prefix[prefix.len() - 1] + v);
    }
    let threshold = cfg.threshold_px_per_frame;
    for t in ctx..=n - ctx {
        let before = (prefix[t] - prefix[t - ctx]) / ctx as f64;
        let after = (prefix[t + ctx] - prefix[t]) / ctx as f64;
        let change = before.abs() > threshold
            && after.abs() > threshold
            && before.signum() != after.signum();
        if !change {
            continue;
        }
        match runs.last_mut() {
            Some(run) if run.1 + 1 == t => run.1 = t,
            _ => runs.push((t, t)),
        }
    }
    runs
}

/// Step 5: one change frame per run.
fn change_points(
    runs: &[(usize, usize)],
    filtered: &[f64],
    velocity: &[f64],
    cfg: &LabelConfig,
) -> Vec<usize> {
    runs.iter()
        .map(|&(first, last)| match cfg.change_point {
            ChangePoint::RunCentre => (first + last) / 2,
            ChangePoint::Extremum => {
                // Rising before the change (velocity > 0) → the change is the maximum.
                let ctx = cfg.context_frames;
                let before: f64 = velocity[first - ctx..first].iter().sum();
                let sign = if before > 0.0 { 1.0 } else { -1.0 };
                let mut best = first;
                for t in first..=last {
                    if sign * filtered[t] > sign * filtered[best] {
                        best = t;
                    }
                }
                best
            }
        })
        .collect()
}

/// Bow-change frames of a vertical wrist track `y` (pixels, y down) at `fps`.
///
/// ```
/// use pose_preproc::{labels::bow_changes_from_y, LabelConfig};
/// // Up for 30 frames, down for 30, up for 30: changes at frames 30 and 60.
/// let y: Vec<f64> = (0..90).map(|t| match t { 0..=29 => 3.0 * t as f64, 30..=59 => 180.0 - 3.0 * t as f64, _ => 3.0 * t as f64 - 180.0 }).collect();
/// assert_eq!(bow_changes_from_y(&y, 30.0, &LabelConfig::default())?, vec![30, 60]);
/// # Ok::<(), pose_preproc::PosePreprocError>(())
/// ```
pub fn bow_changes_from_y(y: &[f64], fps: f64, cfg: &LabelConfig) -> Result<Vec<usize>> {
    let filtered = lowpass(y, fps, cfg)?;
    let velocity = smoothed_velocity(&filtered, cfg)?;
    let runs = detection_runs(&velocity, cfg);
    Ok(change_points(&runs, &filtered, &velocity, cfg))
}

/// Bow-change frames of `motion` (from its right-wrist y), or why there are none: a clip too
/// short for the zero-phase filter ([`PosePreprocError::ClipTooShort`]) or a non-finite value.
pub fn bow_change_labels_checked(motion: &Motion, cfg: &LabelConfig) -> Result<Vec<usize>> {
    let y: Vec<f64> = motion
        .joint(Joint::RWrist)
        .column(1)
        .iter()
        .map(|&v| f64::from(v))
        .collect();
    bow_changes_from_y(&y, motion.fps(), cfg)
}

/// Bow-change frames of `motion`; empty when the clip is too short to label (≤ 15 frames with
/// the defaults) or holds a non-finite value — use [`bow_change_labels_checked`] to know why.
///
/// ```
/// use ndarray::Array3;
/// use pose_preproc::{bow_change_labels, LabelConfig};
/// let still = skeleton::Motion::new(30.0, Array3::zeros((120, 10, 2)))?;
/// assert!(bow_change_labels(&still, &LabelConfig::default()).is_empty());
/// # Ok::<(), skeleton::SkeletonError>(())
/// ```
pub fn bow_change_labels(motion: &Motion, cfg: &LabelConfig) -> Vec<usize> {
    bow_change_labels_checked(motion, cfg).unwrap_or_default()
}

/// The 0/1 per-frame label sequence (SPEC §2) of change frames in a clip of `frames` frames.
///
/// ```
/// assert_eq!(pose_preproc::labels::indicator(&[1, 3], 5), vec![0, 1, 0, 1, 0]);
/// ```
pub fn indicator(changes: &[usize], frames: usize) -> Vec<u8> {
    let mut out = vec![0u8; frames];
    for &c in changes {
        if let Some(v) = out.get_mut(c) {
            *v = 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle(changes: &[usize], len: usize, speed: f64) -> Vec<f64> {
        let mut y = vec![0.0; len];
        let mut dir = 1.0;
        for t in 1..len {
            if changes.contains(&t) {
                dir = -dir;
            }
            y[t] = y[t - 1] + dir * speed;
        }
        y
    }

    #[test]
    fn symmetric_strokes_give_exact_changes_both_ways() {
        let y = triangle(&[40, 80, 120], 160, 4.0);
        for mode in [ChangePoint::Extremum, ChangePoint::RunCentre] {
            let cfg = LabelConfig {
                change_point: mode,
                ..Default::default()
            };
            let got = bow_changes_from_y(&y, 30.0, &cfg).unwrap();
            assert_eq!(got, vec![39, 79, 119], "{mode:?}");
        }
    }

    #[test]
    fn slow_motion_is_below_threshold() {
        let y = triangle(&[40, 80], 120, 0.5);
        assert!(bow_changes_from_y(&y, 30.0, &LabelConfig::default())
            .unwrap()
            .is_empty());
        let cfg = LabelConfig {
            threshold_px_per_frame: 0.2,
            ..Default::default()
        };
        assert_eq!(bow_changes_from_y(&y, 30.0, &cfg).unwrap().len(), 2);
    }

    #[test]
    fn too_short_and_nan_are_reported() {
        let cfg = LabelConfig::default();
        assert!(matches!(
            bow_changes_from_y(&[0.0; 15], 30.0, &cfg),
            Err(PosePreprocError::ClipTooShort {
                frames: 15,
                needed: 16
            })
        ));
        assert!(bow_changes_from_y(&[0.0; 16], 30.0, &cfg)
            .unwrap()
            .is_empty());
        let mut y = vec![0.0; 40];
        y[7] = f64::NAN;
        assert!(matches!(
            bow_changes_from_y(&y, 30.0, &cfg),
            Err(PosePreprocError::NonFinite { frame: 7 })
        ));
    }
}
