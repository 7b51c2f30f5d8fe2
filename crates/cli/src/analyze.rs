//! `violin-skeleton analyze`: f0, notes with fingering, bow changes, beats, downbeats, tempo
//! and arousal of a recording, written as `analysis.json` (ARCHITECTURE.md's schema) by the
//! same [`Pipeline::analyze`] that `generate` uses.
//!
//! JSON has no NaN, so unvoiced f0 frames are written as `0` (mir_eval's convention);
//! `voiced_prob` still says how likely each frame is voiced. `sample_rate` is the input
//! file's rate; the analysis itself runs at 22 050 Hz. A note whose pitch no violin place
//! plays (below the open G) has no `string`/`position`/`finger` fields.
//!
//! A MIDI file (`.mid`, `.midi`) gives the same schema with `"source": "midi"`: every note
//! as the file has it (with `velocity`; overlapping notes kept as double stops), beats,
//! downbeats and meter from the file, bow changes and directions from the slur rules,
//! arousal from velocity and note density, f0 of the highest sounding note and
//! `sample_rate` 0.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use violin_skeleton::{Analysis, Pipeline};

use crate::batch::BatchArgs;
use crate::beat_hint_args::BeatHintArgs;
use crate::contract::{check_outputs, named};
use crate::error::CliError;
use crate::fingering_args::FingeringArgs;
use crate::generate::{is_midi, with_input, AnalysisWeights};
use crate::limits::InputLimits;
use crate::output::write_atomically;
use crate::Reporter;

/// Arguments of `analyze`.
#[derive(Debug, Args)]
#[command(
    after_help = "Examples:\n  violin-skeleton analyze take1.wav -o analysis.json\n  violin-skeleton analyze take1.flac --f0-fps 30 -o take1_analysis.json\n  violin-skeleton analyze minuet.wav --time-signature 3/4 --tempo-bpm 120 -o minuet.json\n  violin-skeleton analyze piece.mid -o piece_analysis.json --planner learned --sul G@12-20"
)]
pub struct AnalyzeArgs {
    /// Audio file (wav, flac, mp3, ogg) or MIDI file (.mid, .midi); or a folder: every such
    /// file under it, in parallel, `NAME.json` files mirrored under `-o` (batch mode).
    pub input: PathBuf,
    /// Output JSON file (batch mode: the output folder).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Write f0 at this frame rate (e.g. 30 for the skeleton) instead of the tracker's own
    /// 11.6 ms hop.
    #[arg(long)]
    pub f0_fps: Option<f64>,
    /// Network weight files (default: the embedded ones).
    #[command(flatten)]
    pub weights: AnalysisWeights,
    /// Fingering planner and style.
    #[command(flatten)]
    pub fingering: FingeringArgs,
    /// Input limits.
    #[command(flatten)]
    pub limits: InputLimits,
    /// What is known of the beat.
    #[command(flatten)]
    pub beat_hints: BeatHintArgs,
    /// Batch mode (a folder as input).
    #[command(flatten)]
    pub batch: BatchArgs,
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
    args.beat_hints.check(args.weights.beats, &args.input)?;
    if args.input.is_dir() {
        return run_folder(args, report);
    }
    let mut inputs = vec![named("input", &args.input)];
    inputs.extend(args.weights.inputs());
    check_outputs(&inputs, &[named("-o", &args.output)])?;
    let pipeline = pipeline_of(args);
    if is_midi(&args.input) {
        return run_midi(args, &pipeline, report);
    }
    let t0 = Instant::now();
    let bar = report.progress(1, "analysing (audio seconds)");
    let (mut analysis, stages) = pipeline.analyze_file_timed(&args.input, |done_s, total_s| {
        if let Some(t) = total_s {
            bar.set_length(t.ceil() as u64);
        }
        bar.set_position(done_s.floor() as u64);
    })?;
    resample_f0(&mut analysis, args.f0_fps);
    let analysed = t0.elapsed();
    bar.finish_and_clear();
    let t2 = Instant::now();
    write_atomically(&args.output, |w| {
        serde_json::to_writer(w, &analysis).map_err(|e| e.to_string())
    })?;
    let written = t2.elapsed();

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
    let ms = |s: f64| s * 1e3;
    report.line(&format!(
        "timing: decode {:.1} ms, analyze {:.1} ms, write {:.1} ms, total {:.1} ms \
         (stages: resample {:.1} ms, pitch {:.1} ms, beats {:.1} ms, bowing {:.1} ms, arousal {:.1} ms; \
         the pitch/beats side and the networks run at once)",
        ms(stages.decode_s),
        ms(analysed.as_secs_f64() - stages.decode_s),
        ms(written.as_secs_f64()),
        ms(t0.elapsed().as_secs_f64()),
        ms(stages.resample_s),
        ms(stages.pitch_s),
        ms(stages.beats_s),
        ms(stages.bowing_s),
        ms(stages.arousal_s),
    ));
    Ok(())
}

/// The pipeline the flags describe.
fn pipeline_of(args: &AnalyzeArgs) -> Pipeline {
    let builder = args
        .fingering
        .apply(args.weights.apply(Pipeline::builder()));
    args.beat_hints.apply(args.limits.apply(builder)).build()
}

/// `analyze DIR -o OUTDIR`: every music file under `DIR` (see [`crate::batch`]).
fn run_folder(args: &AnalyzeArgs, report: &Reporter) -> Result<(), CliError> {
    crate::batch::check_output_folder(&args.input, &args.output)?;
    let plan = crate::batch::plan(&args.input, &args.output, Some("json"))?;
    let pipeline = pipeline_of(args);
    crate::batch::run_batch(
        "analyze",
        &args.input,
        &args.output,
        plan,
        &args.batch,
        report,
        |input, output| {
            let analysis = analysis_of(&pipeline, input, args.f0_fps, |_, _| {})?;
            write_atomically(output, |w| {
                serde_json::to_writer(w, &analysis).map_err(|e| e.to_string())
            })
        },
    )
}

/// Puts the f0 track at `fps` frames per second (`None`: the tracker's own hop).
fn resample_f0(analysis: &mut Analysis, fps: Option<f64>) {
    if let Some(fps) = fps {
        analysis.f0 = violin_skeleton::pitch_track::PitchTrack::from_f0_track(&analysis.f0)
            .resample_to_fps(fps)
            .to_f0_track();
    }
}

/// The analysis of one recording or MIDI file (what `analyze` writes; batch mode runs it
/// per file).
pub fn analysis_of(
    pipeline: &Pipeline,
    input: &Path,
    f0_fps: Option<f64>,
    on_progress: impl FnMut(f64, Option<f64>),
) -> Result<Analysis, CliError> {
    let mut analysis = if is_midi(input) {
        pipeline.analyze_midi_file(input)
    } else {
        pipeline.analyze_file(input, on_progress)
    }
    .map_err(|e| with_input(e, input))?;
    resample_f0(&mut analysis, f0_fps);
    Ok(analysis)
}

/// `analyze` on a MIDI file.
fn run_midi(args: &AnalyzeArgs, pipeline: &Pipeline, report: &Reporter) -> Result<(), CliError> {
    let t0 = Instant::now();
    let mut analysis = pipeline
        .analyze_midi_file(&args.input)
        .map_err(|e| with_input(e, &args.input))?;
    resample_f0(&mut analysis, args.f0_fps);
    let analysed = t0.elapsed();
    let t1 = Instant::now();
    write_atomically(&args.output, |w| {
        serde_json::to_writer(w, &analysis).map_err(|e| e.to_string())
    })?;
    let written = t1.elapsed();
    let placed = analysis
        .notes
        .iter()
        .filter(|n| n.fingering.is_some())
        .count();
    let meter = analysis.meter.map_or_else(String::new, |m| {
        format!(", {} beats per bar", m.beats_per_bar)
    });
    report.line(&format!(
        "{} (MIDI): {:.1} s → {} notes ({placed} fingered), {} bow changes, {:.1} bpm ({} beats, {} downbeats{meter}) written to {}",
        args.input.display(),
        analysis.duration_s,
        analysis.notes.len(),
        analysis.bow_changes_s.len(),
        analysis.tempo_bpm,
        analysis.beats_s.len(),
        analysis.downbeats_s.len(),
        args.output.display()
    ));
    report.line(&format!(
        "timing: read+analyse {:.1} ms, write {:.1} ms, total {:.1} ms",
        analysed.as_secs_f64() * 1e3,
        written.as_secs_f64() * 1e3,
        t0.elapsed().as_secs_f64() * 1e3
    ));
    Ok(())
}
