//! Configuration of the preprocessing and labelling steps (defaults from SPEC §3).

use serde::{Deserialize, Serialize};

use crate::error::{PosePreprocError, Result};

/// All settings of [`crate::preprocess_dir`]; `Default` is SPEC §3.
///
/// ```
/// let cfg = pose_preproc::PreprocConfig::default();
/// assert_eq!((cfg.fps, cfg.confidence_threshold, cfg.max_gap_frames, cfg.median_window), (30.0, 0.05, 15, 3));
/// assert_eq!(cfg.labels.threshold_px_per_frame, 1.0);
/// // Any field may be left out of a JSON config.
/// let cfg: pose_preproc::PreprocConfig = serde_json::from_str(r#"{"max_gap_frames": 5}"#).unwrap();
/// assert_eq!((cfg.max_gap_frames, cfg.median_window), (5, 3));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PreprocConfig {
    /// Frame rate of the source video (OpenPose files do not record it).
    pub fps: f64,
    /// A keypoint with a lower confidence (or absent) is missing.
    pub confidence_threshold: f32,
    /// Gaps of at most this many frames are filled by linear interpolation; longer gaps are
    /// held at the nearest valid value and reported.
    pub max_gap_frames: usize,
    /// Median window (odd) applied to every coordinate after centring; 1 disables it.
    pub median_window: usize,
    /// Subtract the per-video mean of all kept joints (SPEC §3 step 4).
    pub center: bool,
    /// How the performer is chosen and followed.
    pub performer: PerformerConfig,
    /// Bow-change labelling.
    pub labels: LabelConfig,
}

impl Default for PreprocConfig {
    fn default() -> Self {
        Self {
            fps: 30.0,
            confidence_threshold: 0.05,
            max_gap_frames: 15,
            median_window: 3,
            center: true,
            performer: PerformerConfig::default(),
            labels: LabelConfig::default(),
        }
    }
}

impl PreprocConfig {
    /// Checks every value, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        let bad = |what: String| Err(PosePreprocError::InvalidConfig(what));
        if !(self.fps.is_finite() && self.fps > 0.0) {
            return bad(format!("fps must be positive, got {}", self.fps));
        }
        if !(0.0..=1.0).contains(&self.confidence_threshold) {
            return bad(format!(
                "confidence_threshold must be in [0, 1], got {}",
                self.confidence_threshold
            ));
        }
        if self.median_window == 0 || self.median_window.is_multiple_of(2) {
            return bad(format!(
                "median_window must be odd, got {}",
                self.median_window
            ));
        }
        self.performer.validate()?;
        self.labels.validate()
    }
}

/// How the performer is picked among the people OpenPose found, and followed.
///
/// A person is a *candidate* when at least `min_confident_joints` of our ten joints are
/// confident. Its *score* is the mean confidence of the ten joints × the diagonal (px) of the
/// bounding box of its confident joints. Its *distance* to the performer is the mean pixel
/// distance over the joints confident in both (at least 3). See [`crate::performer`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PerformerConfig {
    /// Minimum confident joints (of 10) for a detection to be a candidate at all.
    pub min_confident_joints: usize,
    /// The performer is the best track over these first frames (default: the whole clip, so
    /// persistence counts and a bystander who is there only at the start is not chosen).
    pub start_frames: usize,
    /// Weight of the wrists' activity in the start choice (0: score alone).
    pub activity_weight: f32,
    /// A candidate follows the performer when its distance is at most this fraction of the
    /// performer's size (bounding-box diagonal).
    pub max_step_fraction: f32,
    /// After this many frames without the performer, a candidate anywhere may take over …
    pub reacquire_after_frames: usize,
    /// … if it can be followed through this many further frames (a one-frame detection never
    /// becomes the performer) …
    pub confirm_frames: usize,
    /// … and scores at least this fraction of the performer's usual score.
    pub min_score_ratio: f32,
}

impl Default for PerformerConfig {
    fn default() -> Self {
        Self {
            min_confident_joints: 4,
            start_frames: 1_000_000,
            activity_weight: 4.0,
            max_step_fraction: 0.5,
            reacquire_after_frames: 15,
            confirm_frames: 5,
            min_score_ratio: 0.5,
        }
    }
}

impl PerformerConfig {
    fn validate(&self) -> Result<()> {
        let bad = |what: String| Err(PosePreprocError::InvalidConfig(what));
        if !(1..=10).contains(&self.min_confident_joints) {
            return bad(format!(
                "performer.min_confident_joints must be 1..=10, got {}",
                self.min_confident_joints
            ));
        }
        if self.start_frames == 0 {
            return bad("performer.start_frames must be at least 1".into());
        }
        if !(self.max_step_fraction.is_finite() && self.max_step_fraction > 0.0) {
            return bad(format!(
                "performer.max_step_fraction must be positive, got {}",
                self.max_step_fraction
            ));
        }
        if !(self.activity_weight.is_finite() && self.activity_weight >= 0.0) {
            return bad(format!(
                "performer.activity_weight must be ≥ 0, got {}",
                self.activity_weight
            ));
        }
        if !(self.min_score_ratio.is_finite() && self.min_score_ratio >= 0.0) {
            return bad(format!(
                "performer.min_score_ratio must be ≥ 0, got {}",
                self.min_score_ratio
            ));
        }
        Ok(())
    }
}

/// Where a run of detected frames puts its change point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ChangePoint {
    /// The frame inside the run where the low-passed track turns (its maximum after a
    /// rising stroke, its minimum after a falling one). Jitter moves a flat turn around.
    Extremum,
    /// The run's centre, as SPEC §3 words it. Biased towards the slower of the two strokes
    /// when their speeds differ (see the crate README for measurements).
    RunCentre,
    /// The frame inside the run where the mean velocity of the context after it differs most
    /// from the mean velocity before it: the corner of the track, found from 2 × context
    /// frames of velocity, so jitter moves it less than the extremum.
    VelocityStep,
    /// The knot of the continuous broken line that fits the low-passed track best over
    /// `hinge_window_s` before and after the run, not past the neighbouring changes (least
    /// squares): every frame of both strokes counts, so pixel jitter moves it least.
    #[default]
    Hinge,
}

/// Which coordinate of the bowing wrist the rule labels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum AxisMode {
    /// The coordinate along the bow axis found in the data, relative to the neck; windows in
    /// seconds, threshold in performer sizes per second (SPEC §3).
    #[default]
    Bow,
    /// The original rule: the wrist's image y, windows in frames, threshold in pixels per
    /// frame (the right wrist unless the arm is given).
    Y,
}

/// Which arm bows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum BowArmChoice {
    /// Found from the data ([`crate::axis::find_bow_arm`]); with [`AxisMode::Y`], the right.
    #[default]
    Auto,
    /// The pose estimator's right arm.
    Right,
    /// The pose estimator's left arm (mirrored video, left-handed player).
    Left,
}

/// The bow-change rule of SPEC §3.
///
/// With [`AxisMode::Bow`] (default) the frame-rate-independent fields (`*_s`,
/// `threshold_size_per_s`) apply; with [`AxisMode::Y`] the original's frame and pixel fields
/// (`velocity_median_window`, `context_frames`, `threshold_px_per_frame`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct LabelConfig {
    /// The labelled coordinate.
    pub axis: AxisMode,
    /// The bowing arm.
    pub bow_arm: BowArmChoice,
    /// Butterworth low-pass order.
    pub lowpass_order: usize,
    /// Butterworth cutoff, Hz (the sample rate is the clip's fps).
    pub lowpass_cutoff_hz: f64,
    /// Window of the bow-axis estimate, seconds.
    pub axis_window_s: f64,
    /// Median window applied to the velocity, seconds (rounded to an odd frame count).
    pub velocity_median_s: f64,
    /// Time averaged before and after a candidate frame, seconds (rounded to frames).
    pub context_s: f64,
    /// Both mean speeds must exceed this, in performer sizes (torso lengths) per second.
    pub threshold_size_per_s: f64,
    /// [`ChangePoint::Hinge`]: seconds of track fitted before and after a run of detections.
    pub hinge_window_s: f64,
    /// [`AxisMode::Y`]: median window (odd) applied to the velocity, frames.
    pub velocity_median_window: usize,
    /// [`AxisMode::Y`]: frames averaged before and after a candidate frame.
    pub context_frames: usize,
    /// [`AxisMode::Y`]: both mean velocities must exceed this, pixels of the source video per
    /// frame.
    pub threshold_px_per_frame: f64,
    /// Where a run of detections places its change.
    pub change_point: ChangePoint,
}

impl Default for LabelConfig {
    fn default() -> Self {
        Self {
            axis: AxisMode::Bow,
            bow_arm: BowArmChoice::Auto,
            lowpass_order: 4,
            lowpass_cutoff_hz: 5.0,
            axis_window_s: 4.0,
            velocity_median_s: 0.4,
            context_s: 1.0 / 3.0,
            threshold_size_per_s: 0.12,
            hinge_window_s: 2.0 / 3.0,
            velocity_median_window: 15,
            context_frames: 10,
            threshold_px_per_frame: 1.0,
            change_point: ChangePoint::default(),
        }
    }
}

impl LabelConfig {
    /// The original rule of SPEC §3 (right wrist's image y, 15- and 10-frame windows, 1 px
    /// per frame), with the change point at the run's centre as SPEC words it.
    pub fn original() -> Self {
        Self {
            axis: AxisMode::Y,
            change_point: ChangePoint::RunCentre,
            ..Self::default()
        }
    }

    /// `(median window, context)` in frames at `fps`: the `*_s` fields for [`AxisMode::Bow`]
    /// (median window made odd, both at least 1), the frame fields for [`AxisMode::Y`].
    pub fn windows_frames(&self, fps: f64) -> (usize, usize) {
        match self.axis {
            AxisMode::Y => (self.velocity_median_window, self.context_frames),
            AxisMode::Bow => {
                let median = ((self.velocity_median_s * fps).round() as usize).max(1);
                let median = if median.is_multiple_of(2) {
                    median + 1
                } else {
                    median
                };
                let context = ((self.context_s * fps).round() as usize).max(1);
                (median, context)
            }
        }
    }

    /// Checks every value, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        let bad = |what: String| Err(PosePreprocError::InvalidConfig(what));
        if !(1..=24).contains(&self.lowpass_order) {
            return bad(format!(
                "labels.lowpass_order must be 1..=24, got {}",
                self.lowpass_order
            ));
        }
        if !(self.lowpass_cutoff_hz.is_finite() && self.lowpass_cutoff_hz > 0.0) {
            return bad(format!(
                "labels.lowpass_cutoff_hz must be positive, got {}",
                self.lowpass_cutoff_hz
            ));
        }
        if self.velocity_median_window == 0 || self.velocity_median_window.is_multiple_of(2) {
            return bad(format!(
                "labels.velocity_median_window must be odd, got {}",
                self.velocity_median_window
            ));
        }
        if self.context_frames == 0 {
            return bad("labels.context_frames must be at least 1".into());
        }
        for (name, v) in [
            ("axis_window_s", self.axis_window_s),
            ("velocity_median_s", self.velocity_median_s),
            ("context_s", self.context_s),
            ("hinge_window_s", self.hinge_window_s),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return bad(format!("labels.{name} must be positive, got {v}"));
            }
        }
        if !(self.threshold_size_per_s.is_finite() && self.threshold_size_per_s >= 0.0) {
            return bad(format!(
                "labels.threshold_size_per_s must be ≥ 0, got {}",
                self.threshold_size_per_s
            ));
        }
        if !(self.threshold_px_per_frame.is_finite() && self.threshold_px_per_frame >= 0.0) {
            return bad(format!(
                "labels.threshold_px_per_frame must be ≥ 0, got {}",
                self.threshold_px_per_frame
            ));
        }
        Ok(())
    }
}
