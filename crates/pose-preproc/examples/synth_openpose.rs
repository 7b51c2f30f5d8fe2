//! Writes a synthetic OpenPose directory (the test generator: a violinist with known bow
//! changes, 3 px jitter, dropouts, a bystander, one-frame false detections), then times
//! `preprocess_dir` on it and scores the labels.
//!
//! ```sh
//! cargo run --release -p pose-preproc --example synth_openpose -- /tmp/pose10k 10000 1 body25
//! violin-skeleton pose-labels /tmp/pose10k -o /tmp/labels.json
//! ```
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[path = "../tests/common/mod.rs"]
mod common;

use std::path::PathBuf;
use std::time::Instant;

use common::{detectable, generate, write_openpose_dir, SynthConfig};
use pose_preproc::metrics::match_events;
use pose_preproc::{preprocess_dir, PreprocConfig};
use skeleton::PoseLayout;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(dir) = args.get(1).map(PathBuf::from) else {
        eprintln!("usage: synth_openpose DIR [FRAMES=10000] [SEED=1] [body25|coco18]");
        std::process::exit(2);
    };
    let frames: usize = args.get(2).map_or(10_000, |s| s.parse().expect("FRAMES"));
    let seed: u64 = args.get(3).map_or(1, |s| s.parse().expect("SEED"));
    let layout = match args.get(4).map(String::as_str) {
        Some("coco18") => PoseLayout::Coco18,
        _ => PoseLayout::Body25,
    };
    let clip = generate(&SynthConfig::standard(frames, layout, seed));
    write_openpose_dir(&dir, &clip, "synth");
    let truth_path = dir.with_extension("truth.json");
    let truth = serde_json::json!({ "bow_change_frames": clip.bow_changes });
    std::fs::write(&truth_path, truth.to_string()).unwrap();
    eprintln!(
        "wrote {frames} frames ({layout:?}) to {} and the true bow changes to {}",
        dir.display(),
        truth_path.display()
    );

    let t0 = Instant::now();
    let raw = pose_preproc::read_openpose_dir(&dir).unwrap();
    eprintln!(
        "read_openpose_dir alone: {:.1} ms ({} files)",
        t0.elapsed().as_secs_f64() * 1e3,
        raw.source_files
    );
    let t0 = Instant::now();
    let track = preprocess_dir(&dir, &PreprocConfig::default()).unwrap();
    let elapsed = t0.elapsed();
    let found = match_events(
        &track.bow_change_frames,
        &detectable(&clip.bow_changes, frames),
        2,
    );
    eprintln!(
        "preprocess_dir: {:.1} ms for {frames} frames; bow changes P {:.3} R {:.3} F1 {:.3} (±2 frames)",
        elapsed.as_secs_f64() * 1e3,
        found.precision,
        found.recall,
        found.f1
    );
}
