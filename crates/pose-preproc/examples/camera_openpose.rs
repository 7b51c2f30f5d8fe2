//! Writes a synthetic OpenPose directory made from the project's motion synthesis seen
//! through a random camera (`tests/common/camera_clip.rs`: yaw, roll, distance, mirroring,
//! frame rate, jitter, dropouts, swaps, bystanders), its true bow changes beside it
//! (`DIR.truth.json`), then times `preprocess_dir` on it (reading and parsing included)
//! and scores the labels at ±100 ms.
//!
//! ```sh
//! cargo run --release -p pose-preproc --example camera_openpose -- /tmp/cam60 --kind mirrored --seed 7 --duration 180
//! violin-skeleton pose-labels /tmp/cam60 --fps 60 -o /tmp/labels.json
//! ```
//!
//! `--kind` is one of `frontal`, `side`, `mirrored` (mirrored + rolled + 50 px, 60 fps),
//! `25` (any camera at 25 fps), `random` (default); `--fps F` overrides the frame rate.
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[path = "../tests/common/mod.rs"]
mod common;

use std::path::PathBuf;
use std::time::Instant;

use common::camera_clip::{generate_clip, CameraKind, ClipSpec};
use common::write_people_dir;
use pose_preproc::metrics::match_events_s;
use pose_preproc::{preprocess_dir, PreprocConfig};

fn arg(args: &[String], name: &str) -> Option<String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .cloned()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(dir) = args
        .get(1)
        .filter(|a| !a.starts_with("--"))
        .map(PathBuf::from)
    else {
        eprintln!("usage: camera_openpose DIR [--kind frontal|side|mirrored|25|random] [--seed N] [--duration S] [--fps F]");
        std::process::exit(2);
    };
    let kind = match arg(&args, "--kind").as_deref() {
        Some("frontal") => CameraKind::Frontal,
        Some("side") => CameraKind::Side,
        Some("mirrored") => CameraKind::MirroredRolledSmall60,
        Some("25") => CameraKind::Any25,
        _ => CameraKind::Random,
    };
    let seed: u64 = arg(&args, "--seed").map_or(1, |s| s.parse().expect("--seed"));
    let duration: f64 = arg(&args, "--duration").map_or(60.0, |s| s.parse().expect("--duration"));
    let mut spec = ClipSpec::random(kind, seed, duration);
    if let Some(f) = arg(&args, "--fps") {
        spec.camera.fps = f.parse().expect("--fps");
    }
    let clip = generate_clip(&spec);
    write_people_dir(&dir, &clip.people, "synth");
    let truth_path = dir.with_extension("truth.json");
    let truth = serde_json::json!({
        "fps": spec.camera.fps,
        "bow_change_s": clip.bow_changes_s,
        "camera": format!("{:?}", spec.camera),
        "layout": format!("{:?}", spec.layout),
    });
    std::fs::write(&truth_path, truth.to_string()).unwrap();
    eprintln!(
        "wrote {} frames ({:?}, {:?}) to {} and the true bow changes to {}",
        clip.people.len(),
        spec.layout,
        spec.camera,
        dir.display(),
        truth_path.display()
    );
    let cfg = PreprocConfig {
        fps: spec.camera.fps,
        ..Default::default()
    };
    let t0 = Instant::now();
    let track = preprocess_dir(&dir, &cfg).unwrap();
    let elapsed = t0.elapsed();
    let pred: Vec<f64> = track
        .bow_change_frames
        .iter()
        .map(|&f| f as f64 / spec.camera.fps)
        .collect();
    let truth: Vec<f64> = clip
        .bow_changes_s
        .iter()
        .copied()
        .filter(|&t| t >= 0.5 && t <= duration - 0.5)
        .collect();
    let m = match_events_s(&pred, &truth, 0.1);
    eprintln!(
        "preprocess_dir (read + parse + clean + label): {:.1} ms for {} files; bow changes P {:.3} R {:.3} F1 {:.3} (±100 ms)",
        elapsed.as_secs_f64() * 1e3,
        track.quality.source_files,
        m.precision,
        m.recall,
        m.f1
    );
}
