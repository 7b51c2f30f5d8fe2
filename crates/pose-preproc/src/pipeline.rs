//! The whole preprocessing: read → performer → fill → centre → smooth → label.

use std::path::Path;

use dsp_mel::filters::{median_filter, EdgeMode};
use ndarray::Axis;
use skeleton::{Motion, JOINT_COUNT};

use crate::config::PreprocConfig;
use crate::error::{PosePreprocError, Result};
use crate::fill::fill_gaps;
use crate::labels::{label_motion, BowLabels};
use crate::performer::select_performer;
use crate::quality::QualityReport;
use crate::read::{read_openpose_dir, Detection, RawPoses};
use crate::swap::{fix_left_right_swaps_within, MAX_SWAP_S};

/// The cleaned skeleton of a video, its bow changes, and how clean the input was.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseTrack {
    /// The performer's ten joints, `(frames, 10, 2)`, filled, centred (unless disabled) and
    /// median-smoothed, at the configured fps. Never NaN.
    pub motion: Motion,
    /// Bow-change frames (SPEC §3 rule on the bowing wrist); empty for clips too short to
    /// label.
    pub bow_change_frames: Vec<usize>,
    /// The labels with the bowing arm, the performer's size and the per-frame confidence;
    /// `None` for clips too short to label.
    pub labels: Option<BowLabels>,
    /// What was found and done.
    pub quality: QualityReport,
}

/// Reads an OpenPose output directory and cleans it into the performer's skeleton (SPEC §3).
///
/// ```no_run
/// let track = pose_preproc::preprocess_dir("take1_openpose".as_ref(), &Default::default())?;
/// println!("{} frames, bow changes at {:?}", track.motion.len(), track.bow_change_frames);
/// println!("{}", serde_json::to_string_pretty(&track.quality).unwrap());
/// # Ok::<(), pose_preproc::PosePreprocError>(())
/// ```
pub fn preprocess_dir(dir: &Path, cfg: &PreprocConfig) -> Result<PoseTrack> {
    cfg.validate()?;
    let raw = read_openpose_dir(dir)?;
    preprocess_poses(&raw, cfg).map_err(|e| match e {
        PosePreprocError::NoPerson { frames, .. } => PosePreprocError::NoPerson {
            dir: dir.to_path_buf(),
            frames,
        },
        PosePreprocError::JointNeverDetected {
            joint, threshold, ..
        } => PosePreprocError::JointNeverDetected {
            dir: dir.to_path_buf(),
            joint,
            threshold,
        },
        other => other,
    })
}

/// [`preprocess_dir`] on poses already read (e.g. from another pose estimator). Errors that
/// name a directory name an empty path.
pub fn preprocess_poses(raw: &RawPoses, cfg: &PreprocConfig) -> Result<PoseTrack> {
    cfg.validate()?;
    let threshold = cfg.confidence_threshold;
    let (chosen, stats) = select_performer(&raw.frames, threshold, &cfg.performer);
    let mut performer: Vec<Option<Detection>> = chosen
        .iter()
        .zip(&raw.frames)
        .map(|(c, people)| c.and_then(|i| people.get(i)).copied())
        .collect();
    let max_swap_frames = ((cfg.fps * MAX_SWAP_S).round() as usize).max(1);
    let left_right_swaps_fixed =
        fix_left_right_swaps_within(&mut performer, threshold, max_swap_frames);
    let wrist_confidence: Vec<[f32; 2]> = performer
        .iter()
        .map(|d| {
            d.map_or([0.0, 0.0], |d| {
                [skeleton::Joint::RWrist, skeleton::Joint::LWrist].map(|j| {
                    let c = d.joints[j.index()][2];
                    if c >= threshold {
                        c
                    } else {
                        0.0
                    }
                })
            })
        })
        .collect();
    let performer: Vec<Option<&Detection>> = performer.iter().map(Option::as_ref).collect();
    let with_performer = performer.iter().filter(|p| p.is_some()).count();
    if with_performer == 0 {
        return Err(PosePreprocError::NoPerson {
            dir: Default::default(),
            frames: raw.frames.len(),
        });
    }
    let mean_confidence = performer
        .iter()
        .flatten()
        .map(|d| d.joints.iter().map(|p| p[2]).sum::<f32>() / JOINT_COUNT as f32)
        .sum::<f32>()
        / with_performer as f32;
    let filled = fill_gaps(&performer, threshold, cfg.max_gap_frames).map_err(|joint| {
        PosePreprocError::JointNeverDetected {
            dir: Default::default(),
            joint: joint.name(),
            threshold,
        }
    })?;
    let mut motion = Motion::new(cfg.fps, filled.frames)?;
    let mut center_offset_px = [0.0, 0.0];
    if cfg.center {
        let (mx, my) = motion.mean_xy();
        center_offset_px = [mx, my];
        motion.center();
    }
    smooth(&mut motion, cfg.median_window)?;

    let mut notes = Vec::new();
    if !raw.skipped.is_empty() {
        let shown: Vec<&str> = raw.skipped.iter().take(5).map(String::as_str).collect();
        notes.push(format!(
            "skipped {} entries: {}{}",
            raw.skipped.len(),
            shown.join(", "),
            if raw.skipped.len() > 5 { ", …" } else { "" }
        ));
    }
    if let Some(file) = &raw.first_bad_keypoint_file {
        notes.push(format!(
            "{} keypoints with a negative or non-numeric (NaN/Infinity) value were dropped as missing, the first in {}",
            raw.bad_keypoints,
            file.display()
        ));
    }
    if raw.missing_frame_files > 0 {
        notes.push(format!(
            "{} frame numbers had no file; they were filled like frames without a performer",
            raw.missing_frame_files
        ));
    }
    let labels = match label_motion(&motion, &cfg.labels, Some(&wrist_confidence)) {
        Ok(labels) => Some(labels),
        Err(PosePreprocError::ClipTooShort { frames, needed }) => {
            notes.push(format!(
                "clip of {frames} frames is too short for bow-change labels (needs {needed}); no labels"
            ));
            None
        }
        Err(e) => return Err(e),
    };
    let bow_change_frames = labels
        .as_ref()
        .map(|l| l.frames.clone())
        .unwrap_or_default();
    let quality = QualityReport {
        frames: motion.len(),
        layout: raw.layout,
        source_files: raw.source_files,
        missing_frame_files: raw.missing_frame_files,
        frames_without_performer: stats.frames_without_performer,
        frames_with_other_people: stats.frames_with_other_people,
        performer_switches_rejected: stats.switches_rejected,
        performer_reacquisitions: stats.reacquisitions,
        mean_confidence,
        filled_joint_frames: filled.filled_joint_frames,
        held_joint_frames: filled.held_joint_frames,
        long_gaps: filled.long_gaps,
        center_offset_px,
        left_right_swaps_fixed,
        bow_changes: bow_change_frames.len(),
        notes,
    };
    Ok(PoseTrack {
        motion,
        bow_change_frames,
        labels,
        quality,
    })
}

/// Median filter (edges: nearest) of every coordinate of every joint over time.
fn smooth(motion: &mut Motion, window: usize) -> Result<()> {
    if window <= 1 {
        return Ok(());
    }
    let mut frames = motion.frames_mut();
    let mut series = Vec::with_capacity(frames.len_of(Axis(0)));
    for mut lane in frames.lanes_mut(Axis(0)) {
        series.clear();
        series.extend(lane.iter().map(|&v| f64::from(v)));
        let smoothed = median_filter(&series, window, EdgeMode::Nearest)?;
        for (v, s) in lane.iter_mut().zip(smoothed) {
            *v = s as f32;
        }
    }
    Ok(())
}
