//! Bow-change F1 (±100 ms) of the labelling rule on synthetic OpenPose clips made from the
//! project's motion synthesis seen through random cameras (`tests/common/camera_clip.rs`),
//! per camera set, per camera yaw and per frame rate, beside the original rule (`--axis y`:
//! `LabelConfig::original()`, the right wrist's image y, run centre).
//!
//! ```sh
//! # tuning seeds
//! cargo run --release -p pose-preproc --example pose_label_eval -- --first-seed 1
//! # held-out seeds (the figures of the README)
//! cargo run --release -p pose-preproc --example pose_label_eval -- --first-seed 5000
//! ```
//!
//! Options: `--first-seed N` (1), `--clips K` per set (8), `--duration S` seconds (40),
//! `--threshold T` sizes per second (the default), `--keep DIR` (write the clips there and keep
//! them), `--clean` (no pose-estimator troubles: the camera alone), `--only SET` (a set whose
//! name starts with SET), `--without TROUBLE` (repeatable: jitter, dropouts, swaps, absences,
//! low_confidence, occlusion, bystanders, entering, false).
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[path = "../tests/common/mod.rs"]
mod common;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

use common::camera_clip::{generate_clip, CameraKind, ClipSpec};
use common::write_people_dir;
use pose_preproc::metrics::match_events_s;
use pose_preproc::{preprocess_dir, AxisMode, PreprocConfig};

#[derive(Default, Clone, Copy)]
struct Tally {
    tp: usize,
    fp: usize,
    fn_: usize,
    clips: usize,
}

impl Tally {
    fn add(&mut self, m: &pose_preproc::metrics::EventMatch) {
        self.tp += m.true_positives;
        self.fp += m.false_positives;
        self.fn_ += m.false_negatives;
        self.clips += 1;
    }
    fn f1(&self) -> f64 {
        2.0 * self.tp as f64 / (2 * self.tp + self.fp + self.fn_).max(1) as f64
    }
}

fn arg<T: std::str::FromStr>(args: &[String], name: &str, default: T) -> T {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map_or(default, |v| v.parse().ok().expect(name))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let first_seed: u64 = arg(&args, "--first-seed", 1);
    let clips: usize = arg(&args, "--clips", 8);
    let duration: f64 = arg(&args, "--duration", 40.0);
    let threshold: f64 = arg(
        &args,
        "--threshold",
        PreprocConfig::default().labels.threshold_size_per_s,
    );
    let keep: Option<PathBuf> = args
        .iter()
        .position(|a| a == "--keep")
        .and_then(|i| args.get(i + 1))
        .map(PathBuf::from);
    let clean = args.iter().any(|a| a == "--clean");
    let verbose = args.iter().any(|a| a == "--verbose");
    let change_point: Option<String> = args
        .iter()
        .position(|a| a == "--change-point")
        .and_then(|i| args.get(i + 1))
        .cloned();
    let only: Option<String> = args
        .iter()
        .position(|a| a == "--only")
        .and_then(|i| args.get(i + 1))
        .cloned();
    let tmp = tempfile::tempdir().unwrap();
    let root = keep.clone().unwrap_or_else(|| tmp.path().to_path_buf());

    // [new, old] per set, per yaw bin, per fps.
    let mut by_set: BTreeMap<usize, [Tally; 2]> = BTreeMap::new();
    let mut by_yaw: BTreeMap<i32, [Tally; 2]> = BTreeMap::new();
    let mut by_fps: BTreeMap<u32, [Tally; 2]> = BTreeMap::new();
    let mut arm_right = 0usize;
    let mut frames_total = 0usize;
    let mut seconds = 0.0f64;
    for (k, kind) in CameraKind::ALL.into_iter().enumerate() {
        if only
            .as_ref()
            .is_some_and(|o| !kind.name().starts_with(o.as_str()))
        {
            continue;
        }
        for i in 0..clips {
            let seed = first_seed + 100 * k as u64 + i as u64;
            let mut spec = ClipSpec::random(kind, seed, duration);
            if clean {
                spec.troubles = common::troubles::Troubles::none();
            }
            for (i, a) in args.iter().enumerate() {
                if a == "--without" {
                    spec.troubles
                        .disable(args.get(i + 1).map_or("", String::as_str));
                }
            }
            let clip = generate_clip(&spec);
            let dir = root.join(format!("{}_{seed}", kind.name().replace([' ', '+'], "_")));
            write_people_dir(&dir, &clip.people, "clip");
            let fps = spec.camera.fps;
            let truth: Vec<f64> = clip
                .bow_changes_s
                .iter()
                .copied()
                .filter(|&t| t >= 0.5 && t <= duration - 0.5)
                .collect();
            let mut cells = [None, None];
            for (m, axis) in [AxisMode::Bow, AxisMode::Y].into_iter().enumerate() {
                let mut cfg = PreprocConfig {
                    fps,
                    ..Default::default()
                };
                if axis == AxisMode::Y {
                    cfg.labels = pose_preproc::LabelConfig::original();
                }
                cfg.labels.threshold_size_per_s = threshold;
                if m == 0 {
                    let l = &mut cfg.labels;
                    l.velocity_median_s = arg(&args, "--median-s", l.velocity_median_s);
                    l.context_s = arg(&args, "--context-s", l.context_s);
                    l.lowpass_cutoff_hz = arg(&args, "--cutoff", l.lowpass_cutoff_hz);
                    l.axis_window_s = arg(&args, "--axis-window-s", l.axis_window_s);
                    if let Some(cp) = &change_point {
                        cfg.labels.change_point =
                            serde_json::from_value(serde_json::json!(cp)).unwrap();
                    }
                }
                let t0 = Instant::now();
                let track = preprocess_dir(&dir, &cfg).unwrap();
                if m == 0 {
                    seconds += t0.elapsed().as_secs_f64();
                    frames_total += track.motion.len();
                    let arm = track.labels.as_ref().map(|l| l.arm);
                    // The bowing arm is the right one, or the left in a mirrored image.
                    let want = if spec.camera.mirror {
                        pose_preproc::Arm::Left
                    } else {
                        pose_preproc::Arm::Right
                    };
                    arm_right += usize::from(arm == Some(want));
                }
                let pred: Vec<f64> = track
                    .bow_change_frames
                    .iter()
                    .map(|&f| f as f64 / fps)
                    .collect();
                if verbose && m == 0 {
                    let offs: Vec<i64> = truth
                        .iter()
                        .map(|t| {
                            let near = pred
                                .iter()
                                .min_by(|a, b| (*a - t).abs().total_cmp(&(*b - t).abs()));
                            near.map_or(9999, |p| ((p - t) * 1000.0).round() as i64)
                        })
                        .collect();
                    eprintln!("  nearest prediction − truth, ms: {offs:?}");
                }
                cells[m] = Some(match_events_s(&pred, &truth, 0.1));
            }
            let [Some(new), Some(old)] = cells else {
                unreachable!()
            };
            let yaw_bin = ((spec.camera.yaw_deg + 90.0) / 30.0)
                .floor()
                .clamp(0.0, 5.0) as i32;
            for map_entry in [
                by_set.entry(k).or_default(),
                by_yaw.entry(yaw_bin).or_default(),
                by_fps.entry(fps as u32).or_default(),
            ] {
                map_entry[0].add(&new);
                map_entry[1].add(&old);
            }
            eprintln!(
                "{:<28} seed {seed:>5} yaw {:>6.1} roll {:>5.1} {:>3} px {:>2} fps{} {:?}: {} changes, F1 {:.3} (P {:.3} R {:.3}), --axis y {:.3}",
                kind.name(),
                spec.camera.yaw_deg,
                spec.camera.roll_deg,
                spec.camera.height_px as u32,
                fps,
                if spec.camera.mirror { " mirrored" } else { "" },
                spec.layout,
                truth.len(),
                new.f1,
                new.precision,
                new.recall,
                old.f1
            );
        }
    }
    let clips_total = clips * CameraKind::ALL.len();
    println!(
        "seeds {first_seed}.. ({clips} clips of {duration} s per set), threshold {threshold} sizes/s, F1 at ±100 ms"
    );
    println!("| set | clips | changes | F1 (bow axis) | F1 (--axis y) |\n|---|---|---|---|---|");
    for (k, [new, old]) in &by_set {
        println!(
            "| {} | {} | {} | {:.3} | {:.3} |",
            CameraKind::ALL[*k].name(),
            new.clips,
            new.tp + new.fn_,
            new.f1(),
            old.f1()
        );
    }
    println!("\n| camera yaw | clips | F1 (bow axis) | F1 (--axis y) |\n|---|---|---|---|");
    for (bin, [new, old]) in &by_yaw {
        let lo = -90 + 30 * bin;
        println!(
            "| {lo}…{}° | {} | {:.3} | {:.3} |",
            lo + 30,
            new.clips,
            new.f1(),
            old.f1()
        );
    }
    println!("\n| fps | clips | F1 (bow axis) | F1 (--axis y) |\n|---|---|---|---|");
    for (fps, [new, old]) in &by_fps {
        println!(
            "| {fps} | {} | {:.3} | {:.3} |",
            new.clips,
            new.f1(),
            old.f1()
        );
    }
    println!(
        "\nbowing arm right in {arm_right}/{clips_total} clips; labelling {:.0} frames/s (read + clean + label, debug or release as built)",
        frames_total as f64 / seconds.max(1e-9)
    );
}
