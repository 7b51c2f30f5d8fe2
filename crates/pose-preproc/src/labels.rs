//! Bow-change labels from the bowing wrist (SPEC §3), the training target of the bowing
//! network.
//!
//! 1. the labelled track: by default ([`AxisMode::Bow`]) the bowing wrist's coordinate along
//!    the bow axis, relative to the neck, in performer sizes (see [`crate::axis`]); with
//!    [`AxisMode::Y`] the wrist's image y in pixels (the original rule);
//! 2. low-pass with a Butterworth filter (order 4, 5 Hz at the clip's fps), zero-phase
//!    (`filtfilt`, scipy-equal), so labels are not delayed;
//! 3. velocity `v[t] = s[t+1] − s[t]`, median-filtered (0.4 s, or 15 frames with `Y`);
//! 4. frame `t` is a detection when the mean velocity of the `k` frames before it and of the
//!    `k` frames after it (`k` = 1/3 s, or 10 frames with `Y`) both exceed the threshold
//!    (0.12 performer sizes per second, or 1 px per frame with `Y`) in magnitude and have
//!    opposite signs;
//! 5. each run of consecutive detections becomes one change frame: by default the knot of
//!    the broken line that fits the low-passed track best over 2/3 s before and after the run
//!    (not past the neighbouring changes, [`ChangePoint::Hinge`]); or the frame where the mean
//!    velocity after it differs most from the mean before it ([`ChangePoint::VelocityStep`]);
//!    or where the low-passed track turns ([`ChangePoint::Extremum`]); or the run's centre
//!    ([`ChangePoint::RunCentre`], SPEC's wording).

use dsp_mel::filters::{filtfilt, median_filter, Butterworth, EdgeMode};
use serde::{Deserialize, Serialize};
use skeleton::Motion;

use crate::axis::{
    find_bow_arm, performer_size_px, project, windowed_axis, wrist_relative_to_neck, Arm,
};
use crate::config::{AxisMode, BowArmChoice, ChangePoint, LabelConfig};
use crate::corner::{best_knot, HingeSums};
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

/// Step 2: the zero-phase Butterworth low-pass of `y` sampled at `fps`.
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

/// The frame-level parameters of steps 3–4.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RuleFrames {
    /// Median window of the velocity (odd), frames.
    pub median_window: usize,
    /// Frames averaged before and after a candidate.
    pub context: usize,
    /// Threshold on both mean velocities, track units per frame.
    pub threshold: f64,
    /// Frames before and after a run that [`ChangePoint::Hinge`] fits.
    pub fit: usize,
}

impl RuleFrames {
    /// The parameters of `cfg` at `fps` (threshold per frame in the track's own unit: pixels
    /// for [`AxisMode::Y`], performer sizes for [`AxisMode::Bow`]).
    pub fn new(cfg: &LabelConfig, fps: f64) -> Self {
        let (median_window, context) = cfg.windows_frames(fps);
        let threshold = match cfg.axis {
            AxisMode::Y => cfg.threshold_px_per_frame,
            AxisMode::Bow => cfg.threshold_size_per_s / fps,
        };
        RuleFrames {
            median_window,
            context,
            threshold,
            fit: ((cfg.hinge_window_s * fps).round() as usize).max(2),
        }
    }
}

/// Step 3: velocity of the filtered track (length `len − 1`), median-filtered.
pub fn smoothed_velocity(filtered: &[f64], median_window: usize) -> Result<Vec<f64>> {
    let velocity: Vec<f64> = filtered.windows(2).map(|w| w[1] - w[0]).collect();
    Ok(median_filter(&velocity, median_window, EdgeMode::Nearest)?)
}

/// Step 4: the runs `(first, last)` (inclusive frame indices) of detected frames, given the
/// smoothed velocity.
pub fn detection_runs(velocity: &[f64], rule: &RuleFrames) -> Vec<(usize, usize)> {
    let ctx = rule.context;
    let n = velocity.len();
    let mut runs: Vec<(usize, usize)> = Vec::new();
    if ctx == 0 || n < 2 * ctx {
        return runs;
    }
    let mut prefix = Vec::with_capacity(n + 1);
    prefix.push(0.0f64);
    for v in velocity {
        prefix.push(prefix[prefix.len() - 1] + v);
    }
    for t in ctx..=n - ctx {
        let before = (prefix[t] - prefix[t - ctx]) / ctx as f64;
        let after = (prefix[t + ctx] - prefix[t]) / ctx as f64;
        let change = before.abs() > rule.threshold
            && after.abs() > rule.threshold
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
    (context, fit): (usize, usize),
    mode: ChangePoint,
) -> Vec<usize> {
    let sums = &HingeSums::new(filtered);
    let centre = |i: usize| runs.get(i).map(|&(a, b)| (a + b) / 2);
    runs.iter()
        .enumerate()
        .map(|(i, &(first, last))| match mode {
            ChangePoint::RunCentre => (first + last) / 2,
            ChangePoint::Hinge => {
                // The context around the run, but not past the neighbouring changes.
                let lo = (first.saturating_sub(fit))
                    .max(i.checked_sub(1).and_then(centre).map_or(0, |c| c + 2));
                let hi = (last + fit + 1).min(centre(i + 1).map_or(usize::MAX, |c| c - 1));
                let pad = context / 2;
                let cands = (first.saturating_sub(pad), last + pad);
                best_knot(sums, (lo, hi), cands, (first + last) / 2)
            }
            ChangePoint::VelocityStep => {
                // The frame where the mean velocity of the `context` frames after it differs
                // most from that of the `context` frames before it.
                let n = velocity.len();
                let k = context.max(1);
                let mut best = (f64::NEG_INFINITY, first);
                for t in first.max(k)..=last.min(n.saturating_sub(k)) {
                    let before: f64 = velocity[t - k..t].iter().sum();
                    let after: f64 = velocity[t..t + k].iter().sum();
                    let step = (after - before).abs();
                    if step > best.0 {
                        best = (step, t);
                    }
                }
                best.1
            }
            ChangePoint::Extremum => {
                // Rising before the change (velocity > 0) → the change is the maximum.
                let before: f64 = velocity[first.saturating_sub(context)..first].iter().sum();
                let sign = if before > 0.0 { 1.0 } else { -1.0 };
                let mut best = first;
                for t in first..=last.min(filtered.len().saturating_sub(1)) {
                    if sign * filtered[t] > sign * filtered[best] {
                        best = t;
                    }
                }
                best
            }
        })
        .collect()
}

/// Steps 2–5 on any track at `fps` with the frame-level parameters `rule`.
pub fn bow_changes_from_track(
    track: &[f64],
    fps: f64,
    rule: &RuleFrames,
    cfg: &LabelConfig,
) -> Result<Vec<usize>> {
    if rule.median_window.is_multiple_of(2) {
        return Err(PosePreprocError::InvalidConfig(format!(
            "velocity median window must be odd, got {}",
            rule.median_window
        )));
    }
    let filtered = lowpass(track, fps, cfg)?;
    let velocity = smoothed_velocity(&filtered, rule.median_window)?;
    let runs = detection_runs(&velocity, rule);
    Ok(change_points(
        &runs,
        &filtered,
        &velocity,
        (rule.context, rule.fit),
        cfg.change_point,
    ))
}

/// Bow-change frames of a vertical wrist track `y` (pixels, y down) at `fps` with the
/// original rule's frame and pixel parameters (`velocity_median_window`, `context_frames`,
/// `threshold_px_per_frame`).
///
/// ```
/// use pose_preproc::{labels::bow_changes_from_y, LabelConfig};
/// // Up for 30 frames, down for 30, up for 30: changes at frames 30 and 60.
/// let y: Vec<f64> = (0..90).map(|t| match t { 0..=29 => 3.0 * t as f64, 30..=59 => 180.0 - 3.0 * t as f64, _ => 3.0 * t as f64 - 180.0 }).collect();
/// assert_eq!(bow_changes_from_y(&y, 30.0, &LabelConfig::default())?, vec![30, 60]);
/// # Ok::<(), pose_preproc::PosePreprocError>(())
/// ```
pub fn bow_changes_from_y(y: &[f64], fps: f64, cfg: &LabelConfig) -> Result<Vec<usize>> {
    let y_cfg = LabelConfig {
        axis: AxisMode::Y,
        ..cfg.clone()
    };
    bow_changes_from_track(y, fps, &RuleFrames::new(&y_cfg, fps), cfg)
}

/// The labels of a clip and how they were made.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BowLabels {
    /// Bow-change frames (the clip's frames).
    pub frames: Vec<usize>,
    /// The bowing arm used.
    pub arm: Arm,
    /// The labelled coordinate.
    pub axis: AxisMode,
    /// The performer's size (median torso length), pixels; the unit of the threshold.
    pub size_px: f64,
    /// How much each arm's wrist moves along a line (`[right, left]`, pixels, see
    /// [`crate::axis::bowing_score`]).
    pub arm_scores: [f64; 2],
    /// Per frame, in `[0, 1]`: how far the labels can be trusted there — the bowing wrist's
    /// detection confidence (when known) × the linearity of its motion around that frame.
    pub confidence: Vec<f32>,
}

/// Labels `motion` (see the module documentation). `wrist_confidence`, when given, holds per
/// frame and per arm (`[right, left]`) the pose estimator's confidence in the wrist (0 where
/// it was missing and filled). Fails with [`PosePreprocError::ClipTooShort`] on clips too
/// short for the zero-phase filter, [`PosePreprocError::NonFinite`] on a NaN, and
/// [`PosePreprocError::NoSize`] when the performer has no measurable torso.
pub fn label_motion(
    motion: &Motion,
    cfg: &LabelConfig,
    wrist_confidence: Option<&[[f32; 2]]>,
) -> Result<BowLabels> {
    cfg.validate()?;
    let fps = motion.fps();
    let window = ((cfg.axis_window_s * fps).round() as usize).max(1);
    let (found_arm, arm_scores, found_axis) = find_bow_arm(motion, window);
    let arm = match (cfg.bow_arm, cfg.axis) {
        (BowArmChoice::Right, _) | (BowArmChoice::Auto, AxisMode::Y) => Arm::Right,
        (BowArmChoice::Left, _) => Arm::Left,
        (BowArmChoice::Auto, AxisMode::Bow) => found_arm,
    };
    let rel = wrist_relative_to_neck(motion, arm);
    let axis = if arm == found_arm {
        found_axis
    } else {
        windowed_axis(&rel, window)
    };
    let size_px = match cfg.axis {
        AxisMode::Y => performer_size_px(motion).unwrap_or(0.0),
        AxisMode::Bow => performer_size_px(motion)?,
    };
    let track: Vec<f64> = match cfg.axis {
        AxisMode::Y => motion
            .joint(arm.wrist())
            .column(1)
            .iter()
            .map(|&v| f64::from(v))
            .collect(),
        AxisMode::Bow => project(&rel, &axis).iter().map(|v| v / size_px).collect(),
    };
    let frames = bow_changes_from_track(&track, fps, &RuleFrames::new(cfg, fps), cfg)?;
    let side = usize::from(arm == Arm::Left);
    let confidence = axis
        .linearity()
        .iter()
        .enumerate()
        .map(|(t, &l)| {
            let c = wrist_confidence
                .and_then(|w| w.get(t))
                .map_or(1.0, |w| w[side].clamp(0.0, 1.0));
            (l as f32 * c).clamp(0.0, 1.0)
        })
        .collect();
    Ok(BowLabels {
        frames,
        arm,
        axis: cfg.axis,
        size_px,
        arm_scores,
        confidence,
    })
}

/// Bow-change frames of `motion`, or why there are none: a clip too short for the zero-phase
/// filter ([`PosePreprocError::ClipTooShort`]), a non-finite value, or no performer size.
pub fn bow_change_labels_checked(motion: &Motion, cfg: &LabelConfig) -> Result<Vec<usize>> {
    Ok(label_motion(motion, cfg, None)?.frames)
}

/// Bow-change frames of `motion`; empty when the clip cannot be labelled (≤ 15 frames with
/// the defaults, a non-finite value, no measurable torso) — use [`bow_change_labels_checked`]
/// to know why.
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
        for mode in [
            ChangePoint::Extremum,
            ChangePoint::RunCentre,
            ChangePoint::VelocityStep,
            ChangePoint::Hinge,
        ] {
            let cfg = LabelConfig {
                change_point: mode,
                ..Default::default()
            };
            let got = bow_changes_from_y(&y, 30.0, &cfg).unwrap();
            assert_eq!(got, vec![39, 79, 119], "{mode:?}");
        }
    }

    #[test]
    fn axis_y_is_the_original_rule_on_the_right_wrist() {
        use ndarray::Array3;
        // A body whose right wrist strokes diagonally and left wrist strokes vertically.
        let n = 200;
        let y = triangle(&[37, 90, 131, 170], n, 3.0);
        let left = triangle(&[50, 100, 150], n, 1.5);
        let mut frames = Array3::<f32>::zeros((n, skeleton::JOINT_COUNT, 2));
        for t in 0..n {
            for j in 0..skeleton::JOINT_COUNT {
                frames[[t, j, 0]] = 100.0 + 10.0 * j as f32;
                frames[[t, j, 1]] = 20.0 * j as f32;
            }
            frames[[t, 4, 0]] = 300.0 - 0.7 * y[t] as f32;
            frames[[t, 4, 1]] = 100.0 + y[t] as f32;
            frames[[t, 7, 1]] = 100.0 + left[t] as f32;
        }
        let motion = Motion::new(30.0, frames).unwrap();
        let original = LabelConfig::original();
        let got = label_motion(&motion, &original, None).unwrap();
        let right_y: Vec<f64> = (0..n)
            .map(|t| f64::from(motion.frames()[[t, 4, 1]]))
            .collect();
        assert_eq!(
            got.frames,
            bow_changes_from_y(&right_y, 30.0, &original).unwrap()
        );
        assert_eq!((got.arm, got.axis), (Arm::Right, AxisMode::Y));
        // The default finds the right arm (it moves most along a line) and the same changes.
        let found = label_motion(&motion, &LabelConfig::default(), None).unwrap();
        assert_eq!(found.arm, Arm::Right);
        assert_eq!(found.frames.len(), 4);
        for (a, b) in found.frames.iter().zip([37, 90, 131, 170]) {
            assert!(a.abs_diff(b) <= 2, "{:?}", found.frames);
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
