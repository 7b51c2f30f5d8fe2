//! What preprocessing found and did: the quality report written beside the labels.

use serde::{Deserialize, Serialize};
use skeleton::{Joint, PoseLayout};

/// A run of frames in which one joint of the performer was missing for longer than
/// `max_gap_frames` (or at the start/end of the clip): it was held at the nearest valid value,
/// not invented by interpolation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Gap {
    /// The joint (serialised by name, e.g. `"r_wrist"`).
    pub joint: Joint,
    /// First missing frame.
    pub start_frame: usize,
    /// Number of missing frames.
    pub len: usize,
}

/// What [`crate::preprocess_dir`] found and did.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct QualityReport {
    /// Frames in the output (first to last frame number of the files).
    pub frames: usize,
    /// Body model of the files.
    pub layout: PoseLayout,
    /// Keypoint files read.
    pub source_files: usize,
    /// Frame numbers without a file (treated as frames without a performer).
    pub missing_frame_files: usize,
    /// Frames in which no plausible performer was found (all joints then filled).
    pub frames_without_performer: usize,
    /// Frames with at least one other candidate person besides the performer.
    pub frames_with_other_people: usize,
    /// Frames where choosing by score alone would have switched to someone else.
    pub performer_switches_rejected: usize,
    /// Times the performer was re-acquired at a new place after a long absence.
    pub performer_reacquisitions: usize,
    /// Mean confidence of the performer's ten joints over the frames with a performer.
    pub mean_confidence: f32,
    /// Joint-frames filled by linear interpolation (gaps up to `max_gap_frames`).
    pub filled_joint_frames: usize,
    /// Joint-frames held at the nearest valid value (long gaps and gaps at the clip's ends).
    pub held_joint_frames: usize,
    /// Gaps longer than `max_gap_frames`, per joint.
    pub long_gaps: Vec<Gap>,
    /// The `(x, y)` offset subtracted by centring, pixels (0, 0 when centring is off).
    pub center_offset_px: [f32; 2],
    /// Joint-pair frames whose left and right the pose estimator had swapped, swapped back.
    pub left_right_swaps_fixed: usize,
    /// Bow changes found (0 when the clip is too short to label; see `notes`).
    pub bow_changes: usize,
    /// Anything else worth knowing (e.g. a clip too short to label).
    pub notes: Vec<String>,
}
