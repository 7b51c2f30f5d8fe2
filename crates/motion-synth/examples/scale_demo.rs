//! A 10 s G-major scale étude at 100 bpm (slurs, détaché, a held final note, beats,
//! downbeats and a rising arousal curve) → motion, GIF, BVH and metrics; then the time to
//! synthesise 3 minutes of motion.
//!
//! ```sh
//! cargo run --release -p motion-synth --example scale_demo -- [OUT_DIR] [--gif PATH]
//! ```
//!
//! Writes `OUT_DIR/{performance.json, motion.json, scale_demo.bvh, scale_demo.gif,
//! metrics.json}` (default `OUT_DIR` = `target/scale_demo`; `--gif` puts the GIF elsewhere).

use std::path::PathBuf;
use std::time::Instant;

use fingering::OptimalPlanner;
use motion_synth::metrics::{self, MotionReport};
use motion_synth::{bow, bvh, synthesize_detailed, SynthConfig};
use performance::Note;
use performance::{ArousalCurve, Performance};
use skeleton::MotionFormat;
use skeleton_render::{write_gif_file, RenderConfig};

const BEAT_S: f64 = 0.6; // 100 bpm

/// `(midi, beats, starts a new bow stroke)` for one pass of the étude (16 beats = 4 bars).
fn etude() -> Vec<(u8, f64, bool)> {
    let mut notes = Vec::new();
    // Bar 1: G3 … G4 in eighths, slurred in pairs.
    for (i, m) in [55, 57, 59, 60, 62, 64, 66, 67].into_iter().enumerate() {
        notes.push((m, 0.5, i % 2 == 0));
    }
    // Bar 2: A4 … F#5 détaché (a bow per note), then G5 for a beat.
    for m in [69, 71, 72, 74, 76, 78] {
        notes.push((m, 0.5, true));
    }
    notes.push((79, 1.0, true));
    // Bar 3: down again F#5 … F#4, slurred in fours.
    for (i, m) in [78, 76, 74, 72, 71, 69, 67, 66].into_iter().enumerate() {
        notes.push((m, 0.5, i % 4 == 0));
    }
    // Bar 4: E4 … A3 détaché, then a long G3.
    for m in [64, 62, 60, 59, 57] {
        notes.push((m, 0.5, true));
    }
    notes.push((55, 1.5, true));
    notes
}

/// The étude repeated `passes` times, with beats, downbeats, a rising arousal curve and
/// dynamics following it.
fn performance(passes: usize) -> Result<Performance, performance::PerformanceError> {
    let pass_s = 16.0 * BEAT_S;
    let tail_s = 0.4;
    let duration_s = passes as f64 * pass_s + tail_s;
    let mut notes = Vec::new();
    let mut changes = Vec::new();
    for p in 0..passes {
        let mut t = p as f64 * pass_s;
        for (midi, beats, new_stroke) in etude() {
            let len = beats * BEAT_S;
            if new_stroke && t > 0.0 {
                changes.push(t);
            }
            notes.push(Note::new(t, t + len * 0.97, midi));
            t += len;
        }
    }
    let beats: Vec<f64> = (0..)
        .map(|i| i as f64 * BEAT_S)
        .take_while(|&t| t < duration_s)
        .collect();
    let downbeats: Vec<f64> = beats.iter().copied().step_by(4).collect();
    let values: Vec<f32> = (0..(duration_s * 2.0).ceil() as usize)
        .map(|i| {
            let u = (i as f64 / 2.0 / duration_s) as f32;
            (-0.7 + 1.5 * u + 0.1 * (u * 25.0).sin()).clamp(-1.0, 1.0)
        })
        .collect();
    let dynamics = notes
        .iter()
        .map(|n| (0.3 + 0.6 * n.onset_s / duration_s) as f32)
        .collect();
    Performance::builder(duration_s)
        .notes(notes)
        .bow_changes(changes)
        .beats(beats)
        .downbeats(downbeats)
        .arousal(ArousalCurve::deam(values))
        .dynamics(dynamics)
        .build()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut out_dir = PathBuf::from("target/scale_demo");
    let mut gif_path = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--gif" {
            gif_path = args.next().map(PathBuf::from);
        } else {
            out_dir = PathBuf::from(a);
        }
    }
    std::fs::create_dir_all(&out_dir)?;
    let gif_path = gif_path.unwrap_or_else(|| out_dir.join("scale_demo.gif"));
    let cfg = SynthConfig::default();

    let perf = performance(1)?.with_fingering(&OptimalPlanner::default())?;
    std::fs::write(
        out_dir.join("performance.json"),
        serde_json::to_string_pretty(&perf)?,
    )?;
    let synthesis = synthesize_detailed(&perf, &cfg)?;
    let motion = &synthesis.motion;
    motion.write(out_dir.join("motion.json"), MotionFormat::Json)?;
    bvh::write_bvh_file(motion, out_dir.join("scale_demo.bvh"))?;
    let render = RenderConfig {
        width: 480,
        height: 270,
        fps_out: 15.0,
        scale: 1.2,
        ..RenderConfig::default()
    };
    let t0 = Instant::now();
    write_gif_file(motion, &gif_path, &render)?;
    let gif_ms = t0.elapsed().as_secs_f64() * 1e3;
    let report = MotionReport::measure(&synthesis, &perf);
    let frames = motion.len();
    let naive = bow::plan_naive(
        &bow::change_frames(perf.bow_changes_s(), cfg.fps, frames),
        frames,
        &cfg.bow,
    )?;
    println!(
        "original rule taken literally: {:.1} % of frames outside the bow; planner: {:.1} %",
        100.0 * metrics::bow_range_violations(naive.positions()),
        100.0 * report.bow_range_violations
    );
    std::fs::write(
        out_dir.join("metrics.json"),
        serde_json::to_string_pretty(&report)?,
    )?;
    println!(
        "étude: {:.1} s, {} notes, {} strokes, {} frames",
        perf.duration_s(),
        perf.notes().len(),
        synthesis.bow.strokes().len(),
        motion.len()
    );
    println!("metrics: {}", serde_json::to_string(&report)?);
    println!(
        "GIF {} ({} KiB, {}×{} at {} fps) in {gif_ms:.0} ms",
        gif_path.display(),
        std::fs::metadata(&gif_path)?.len() / 1024,
        render.width,
        render.height,
        render.fps_out
    );

    // Timing: 3 minutes of motion (the étude repeated 19 times), best of 5 runs.
    let long = performance(19)?.with_fingering(&OptimalPlanner::default())?;
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let t = Instant::now();
        let m = synthesize_detailed(&long, &cfg)?;
        best = best.min(t.elapsed().as_secs_f64() * 1e3);
        assert_eq!(m.motion.len(), long.frame_count(cfg.fps));
    }
    println!(
        "synthesis of {:.0} s ({} frames): {best:.1} ms (best of 5)",
        long.duration_s(),
        long.frame_count(cfg.fps)
    );
    Ok(())
}
