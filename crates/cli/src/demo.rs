//! `violin-skeleton demo`: the whole pipeline on the shipped demo clip.
//!
//! The clip is the Minuet in G (Petzold, public domain), encoded in the `corpus` crate and
//! rendered by its built-in bowed-string synthesizer, so its notes and bow changes are
//! known and the demo can say how close the analysis came.

use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use corpus::melodies::minuet_in_g;
use corpus::render::{BowedStringSynth, RenderSettings, Renderer};
use corpus::timing::play;
use pose_preproc::metrics::match_events_s;
use violin_skeleton::fingering::OptimalPlanner;
use violin_skeleton::{Audio, Canvas, Pipeline};

use crate::error::CliError;
use crate::generate::{write_motion, OutFormat};
use crate::output::write_atomically;
use crate::preview::{write_preview, SoundSource};
use crate::Reporter;

/// Arguments of `demo`.
#[derive(Debug, Args)]
#[command(after_help = "Example:\n  violin-skeleton demo            # writes ./demo-out/")]
pub struct DemoArgs {
    /// Output folder.
    #[arg(long, default_value = "demo-out")]
    pub out: PathBuf,
}

const DEMO_RATE_HZ: u32 = 22_050;

fn wav_bytes(samples: &[f32], rate: u32) -> Result<Vec<u8>, String> {
    let mut cursor = Cursor::new(Vec::new());
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::new(&mut cursor, spec).map_err(|e| e.to_string())?;
    let peak = samples.iter().fold(0.0f32, |m, s| m.max(s.abs())).max(1e-9);
    for s in samples {
        w.write_sample((s / peak * 0.7 * 32767.0).round() as i16)
            .map_err(|e| e.to_string())?;
    }
    w.finalize().map_err(|e| e.to_string())?;
    Ok(cursor.into_inner())
}

/// Runs `demo`.
pub fn run(args: &DemoArgs, report: &Reporter) -> Result<(), CliError> {
    let t0 = Instant::now();
    let out = &args.out;
    std::fs::create_dir_all(out).map_err(|e| CliError::Output {
        path: out.clone(),
        reason: format!("cannot create the folder ({e})"),
    })?;
    let bar = report.progress(5, "demo");
    // 1. The clip.
    let mut timeline = play(&minuet_in_g(), 1);
    timeline.assign_fingering(&OptimalPlanner::default());
    let settings = RenderSettings {
        sample_rate_hz: DEMO_RATE_HZ,
        tuning_cents: 0.0,
        seed: 1,
    };
    let samples = BowedStringSynth::default()
        .render(&timeline, &settings)
        .map_err(corpus::CorpusError::from)?;
    let wav = wav_bytes(&samples, DEMO_RATE_HZ).map_err(|reason| CliError::Output {
        path: out.join("demo.wav"),
        reason,
    })?;
    let wav_path = out.join("demo.wav");
    write_atomically(&wav_path, |w| w.write_all(&wav).map_err(|e| e.to_string()))?;
    bar.inc(1);
    // 2. Analysis and motion, through the same pipeline as `generate`.
    let audio = Audio::new(samples, DEMO_RATE_HZ)?;
    let pipeline = Pipeline::default();
    let analysis = pipeline.analyze(&audio)?;
    write_atomically(&out.join("analysis.json"), |w| {
        serde_json::to_writer_pretty(w, &analysis).map_err(|e| e.to_string())
    })?;
    bar.inc(1);
    let motion = pipeline.generate_from_analysis(&analysis)?;
    bar.inc(1);
    // 3. Every output.
    write_motion(
        &motion,
        &out.join("motion.json"),
        OutFormat::Json,
        Canvas::default(),
    )?;
    write_motion(
        &motion,
        &out.join("openpose"),
        OutFormat::Openpose,
        Canvas::default(),
    )?;
    write_motion(
        &motion,
        &out.join("motion.bvh"),
        OutFormat::Bvh,
        Canvas::default(),
    )?;
    write_motion(
        &motion,
        &out.join("motion.glb"),
        OutFormat::Glb,
        Canvas::default(),
    )?;
    bar.inc(1);
    write_preview(&motion, &out.join("preview.gif"), SoundSource::None)?;
    let sound = SoundSource::Audio {
        path: &wav_path,
        embed: false,
    };
    if let Some(note) = write_preview(&motion, &out.join("player.html"), sound)? {
        report.line(&note);
    }
    bar.inc(1);
    bar.finish_and_clear();
    // 4. How close the analysis came to what was played.
    let truth_changes = timeline.bow_changes_s();
    let changes = match_events_s(&analysis.bow_changes_s, &truth_changes, 0.1);
    let onsets: Vec<f64> = timeline.notes.iter().map(|n| n.note.onset_s).collect();
    let found: Vec<f64> = analysis.notes.iter().map(|n| n.onset_s).collect();
    let notes = match_events_s(&found, &onsets, 0.05);
    report.line(&format!(
        "demo: Minuet in G (Petzold), {:.1} s → {} frames in {:.2} s",
        motion.duration_s(),
        motion.len(),
        t0.elapsed().as_secs_f64()
    ));
    report.line(&format!(
        "  notes found {} of {} (onset F1 {:.2} at ±50 ms); bow changes {} of {} (F1 {:.2} at ±0.1 s); {:.0} bpm",
        found.len(),
        onsets.len(),
        notes.f1,
        analysis.bow_changes_s.len(),
        truth_changes.len(),
        changes.f1,
        analysis.tempo_bpm
    ));
    let show = |p: &Path| p.display().to_string();
    report.line(&format!(
        "  look at: {} (open in a browser), {}; data: {}, {}, {}, {}/, {}",
        show(&out.join("player.html")),
        show(&out.join("preview.gif")),
        show(&out.join("motion.json")),
        show(&out.join("motion.bvh")),
        show(&out.join("motion.glb")),
        show(&out.join("openpose")),
        show(&out.join("analysis.json"))
    ));
    Ok(())
}
