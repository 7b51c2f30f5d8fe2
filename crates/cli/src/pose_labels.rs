//! `violin-skeleton pose-labels`: OpenPose JSON directory → cleaned skeleton + bow-change
//! frames (`labels.json`).

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, ValueEnum};
use pose_preproc::{preprocess_dir, ChangePoint, PoseTrack, PreprocConfig};
use violin_skeleton::skeleton::MotionFormat;

use crate::error::CliError;
use crate::output::write_atomically;
use crate::Reporter;

/// Where a run of detected frames puts its bow change.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum ChangePointArg {
    /// The frame where the smoothed wrist height turns (default).
    Extremum,
    /// The centre of the run (SPEC §3's literal rule).
    RunCentre,
}

/// Arguments of `pose-labels`.
#[derive(Debug, Args)]
#[command(
    after_help = "labels.json: {\"fps\": 30, \"bow_change_frames\": [..], \"skeleton\": [[20 floats: x, y of nose, neck, r_shoulder, r_elbow, r_wrist, l_shoulder, l_elbow, l_wrist, r_hip, l_hip], ...], \"quality\": {...}}\n\nExamples:\n  violin-skeleton pose-labels take1_openpose/ -o take1_labels.json\n  violin-skeleton pose-labels take1_openpose/ -o labels.json --skeleton-out take1.csv --threshold-px 1.5"
)]
pub struct PoseLabelsArgs {
    /// OpenPose output directory (one *_keypoints.json per frame, BODY_25 or COCO-18).
    pub dir: PathBuf,
    /// Output labels JSON.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also write the cleaned skeleton: .json, .csv, .npy, or a directory (OpenPose BODY_25).
    #[arg(long)]
    pub skeleton_out: Option<PathBuf>,
    /// Bow-change threshold: mean wrist speed before and after a change, in pixels of the
    /// source video per frame.
    #[arg(long, default_value_t = 1.0)]
    pub threshold_px: f64,
    /// Frame rate of the source video.
    #[arg(long, default_value_t = 30.0)]
    pub fps: f64,
    /// Longest gap (frames) of a missing joint that is filled by interpolation.
    #[arg(long, default_value_t = 15)]
    pub max_gap_frames: usize,
    /// Where a run of detected frames puts its bow change.
    #[arg(long, value_enum, default_value_t = ChangePointArg::Extremum)]
    pub change_point: ChangePointArg,
}

/// Runs `pose-labels`.
pub fn run(args: &PoseLabelsArgs, report: &Reporter) -> Result<(), CliError> {
    if !(args.threshold_px.is_finite() && args.threshold_px >= 0.0) {
        return Err(CliError::Usage(format!(
            "--threshold-px {}: expected a number of pixels ≥ 0",
            args.threshold_px
        )));
    }
    if !(args.fps.is_finite() && args.fps > 0.0) {
        return Err(CliError::Usage(format!(
            "--fps {}: expected a positive frame rate",
            args.fps
        )));
    }
    let skeleton_format = match &args.skeleton_out {
        Some(path) => Some(MotionFormat::from_path(path)?),
        None => None,
    };
    let mut cfg = PreprocConfig {
        fps: args.fps,
        max_gap_frames: args.max_gap_frames,
        ..Default::default()
    };
    cfg.labels.threshold_px_per_frame = args.threshold_px;
    cfg.labels.change_point = match args.change_point {
        ChangePointArg::Extremum => ChangePoint::Extremum,
        ChangePointArg::RunCentre => ChangePoint::RunCentre,
    };

    let t0 = Instant::now();
    let track = preprocess_dir(&args.dir, &cfg)?;
    let processed = t0.elapsed();
    let t1 = Instant::now();
    write_atomically(&args.output, |w| {
        write_labels(&track, w).map_err(|e| e.to_string())
    })?;
    if let (Some(path), Some(format)) = (&args.skeleton_out, skeleton_format) {
        track.motion.write(path, format)?;
    }
    let written = t1.elapsed();

    let q = &track.quality;
    report.line(&format!(
        "{}: {} frames ({:?}, {} files) → {} bow changes written to {}",
        args.dir.display(),
        q.frames,
        q.layout,
        q.source_files,
        track.bow_change_frames.len(),
        args.output.display()
    ));
    report.line(&format!(
        "quality: performer missing in {} frames, {} frames with other people ({} switches rejected), {} joint-frames interpolated, {} held, {} long gaps",
        q.frames_without_performer,
        q.frames_with_other_people,
        q.performer_switches_rejected,
        q.filled_joint_frames,
        q.held_joint_frames,
        q.long_gaps.len()
    ));
    for gap in q.long_gaps.iter().take(5) {
        report.line(&format!(
            "  long gap: {} missing in frames {}–{} ({} frames), held at the nearest valid value",
            gap.joint.name(),
            gap.start_frame,
            gap.start_frame + gap.len - 1,
            gap.len
        ));
    }
    if q.long_gaps.len() > 5 {
        report.line(&format!(
            "  … and {} more (see quality.long_gaps)",
            q.long_gaps.len() - 5
        ));
    }
    for note in &q.notes {
        report.line(&format!("note: {note}"));
    }
    report.line(&format!(
        "timing: read + clean + label {:.1} ms, write {:.1} ms, total {:.1} ms",
        processed.as_secs_f64() * 1e3,
        written.as_secs_f64() * 1e3,
        t0.elapsed().as_secs_f64() * 1e3
    ));
    Ok(())
}

/// `{"fps", "bow_change_frames", "skeleton": [[20 floats] × frames], "quality"}`.
fn write_labels(track: &PoseTrack, w: &mut dyn Write) -> std::io::Result<()> {
    let fps = track.motion.fps();
    if fps.fract() == 0.0 && fps <= 1e9 {
        write!(w, "{{\"fps\":{}", fps as u64)?;
    } else {
        write!(w, "{{\"fps\":{fps}")?;
    }
    w.write_all(b",\"bow_change_frames\":")?;
    serde_json::to_writer(&mut *w, &track.bow_change_frames)?;
    w.write_all(b",\"skeleton\":[")?;
    let mut row: Vec<f32> = Vec::with_capacity(20);
    for (t, frame) in track.motion.frames().outer_iter().enumerate() {
        if t > 0 {
            w.write_all(b",")?;
        }
        row.clear();
        row.extend(frame.iter());
        serde_json::to_writer(&mut *w, &row)?;
    }
    w.write_all(b"],\"quality\":")?;
    serde_json::to_writer(&mut *w, &track.quality)?;
    w.write_all(b"}\n")
}
