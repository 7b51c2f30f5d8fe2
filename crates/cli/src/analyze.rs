//! `violin-skeleton analyze`: f0, notes with fingering, bow changes, beats, downbeats, tempo
//! and arousal of a recording, written as `analysis.json` (ARCHITECTURE.md's schema) by the
//! same [`Pipeline::analyze`] that `generate` uses.
//!
//! JSON has no NaN, so unvoiced f0 frames are written as `0` (mir_eval's convention);
//! `voiced_prob` still says how likely each frame is voiced. `sample_rate` is the input
//! file's rate; the analysis itself runs at 22 050 Hz. A note whose pitch no violin place
//! plays (below the open G) has no `string`/`position`/`finger` fields.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use violin_skeleton::{load_audio, Pipeline};

use crate::error::CliError;
use crate::output::write_atomically;
use crate::Reporter;

/// Arguments of `analyze`.
#[derive(Debug, Args)]
#[command(
    after_help = "Examples:\n  violin-skeleton analyze take1.wav -o analysis.json\n  violin-skeleton analyze take1.flac --f0-fps 30 -o take1_analysis.json"
)]
pub struct AnalyzeArgs {
    /// Audio file (wav, flac, mp3, ogg).
    pub input: PathBuf,
    /// Output JSON file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Write f0 at this frame rate (e.g. 30 for the skeleton) instead of the tracker's own
    /// 11.6 ms hop.
    #[arg(long)]
    pub f0_fps: Option<f64>,
}

/// Runs `analyze`.
pub fn run(args: &AnalyzeArgs, report: &Reporter) -> Result<(), CliError> {
    if let Some(fps) = args.f0_fps {
        if !(fps.is_finite() && (1.0..=1000.0).contains(&fps)) {
            return Err(CliError::Usage(format!(
                "--f0-fps {fps}: expected a frame rate between 1 and 1000"
            )));
        }
    }
    let bar = report.progress(3, "analyze");
    let t0 = Instant::now();
    let audio = load_audio(&args.input)?;
    let decoded = t0.elapsed();
    bar.inc(1);
    let t1 = Instant::now();
    let mut analysis = Pipeline::default().analyze(&audio)?;
    if let Some(fps) = args.f0_fps {
        analysis.f0 = analysis.f0.resampled_to_fps(fps);
    }
    let analysed = t1.elapsed();
    bar.inc(1);
    let t2 = Instant::now();
    write_atomically(&args.output, |w| {
        serde_json::to_writer(w, &analysis).map_err(|e| e.to_string())
    })?;
    let written = t2.elapsed();
    bar.inc(1);
    bar.finish_and_clear();

    let voiced = analysis.f0.hz.iter().filter(|f| **f > 0.0).count();
    report.line(&format!(
        "{}: {:.1} s → {} notes, {:.0}% voiced, {} bow changes, {:.1} bpm ({} beats, {} downbeats) written to {}",
        args.input.display(),
        analysis.duration_s,
        analysis.notes.len(),
        100.0 * voiced as f64 / analysis.f0.hz.len().max(1) as f64,
        analysis.bow_changes_s.len(),
        analysis.tempo_bpm,
        analysis.beats_s.len(),
        analysis.downbeats_s.len(),
        args.output.display()
    ));
    report.line(&format!(
        "timing: decode {:.1} ms, analyze {:.1} ms, write {:.1} ms, total {:.1} ms",
        decoded.as_secs_f64() * 1e3,
        analysed.as_secs_f64() * 1e3,
        written.as_secs_f64() * 1e3,
        t0.elapsed().as_secs_f64() * 1e3
    ));
    Ok(())
}
