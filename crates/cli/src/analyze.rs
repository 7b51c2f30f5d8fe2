//! `violin-skeleton analyze`: f0, notes with fingering, beats, downbeats and tempo of a
//! recording, written as `analysis.json` (ARCHITECTURE.md's schema, the fields that exist so
//! far).
//!
//! JSON has no NaN, so unvoiced f0 frames are written as `0` (mir_eval's convention);
//! `voiced_prob` still says how likely each frame is voiced. `sample_rate` is the input
//! file's rate; the analysis itself runs at 22 050 Hz. A note whose pitch no violin place
//! plays (below the open G) has no `string`/`position`/`finger` fields.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use clap::Args;
use serde_json::{json, Map, Value};
use violin_skeleton::beat_track::{BeatConfig, BeatTracker};
use violin_skeleton::dsp_mel::{load_audio, resample, DEFAULT_ANALYSIS_RATE_HZ};
use violin_skeleton::fingering::{FingeringPlanner, OptimalPlanner};
use violin_skeleton::pitch_track::{segment_notes, Note, NoteConfig, PitchConfig, PitchTracker};

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
    let bar = report.progress(6, "analyze");
    let mut timing: Vec<(&str, Duration)> = Vec::new();
    let t = Instant::now();
    let original = load_audio(&args.input)?;
    timing.push(("decode", t.elapsed()));
    bar.inc(1);
    let t = Instant::now();
    let audio = resample(&original, DEFAULT_ANALYSIS_RATE_HZ)?;
    timing.push(("resample", t.elapsed()));
    bar.inc(1);

    let t = Instant::now();
    let tracker = PitchTracker::new(PitchConfig::default())?;
    let track = tracker.track(audio.samples())?;
    timing.push(("pitch", t.elapsed()));
    bar.inc(1);
    let t = Instant::now();
    let notes = segment_notes(
        &track,
        audio.samples(),
        audio.sample_rate_hz(),
        &NoteConfig::default(),
    )?;
    timing.push(("notes", t.elapsed()));
    bar.inc(1);
    let t = Instant::now();
    let beats = BeatTracker::new(BeatConfig::default())?.track(audio.samples(), Some(&notes))?;
    timing.push(("beats", t.elapsed()));
    bar.inc(1);

    let t = Instant::now();
    let bow_changes_s =
        violin_skeleton::bowing_net::BowChangeDetector::pretrained()?.detect_audio(&audio)?;
    let arousal =
        violin_skeleton::emotion_net::ArousalEstimator::pretrained()?.predict_audio(&audio)?;
    timing.push(("bowing + arousal", t.elapsed()));

    let t = Instant::now();
    let f0 = match args.f0_fps {
        Some(fps) => track.resample_to_fps(fps),
        None => track,
    };
    let document = json!({
        "duration_s": original.duration_s(),
        "sample_rate": original.sample_rate_hz(),
        "f0": {
            "hop_s": f0.hop_s,
            "hz": f0.f0_hz.iter().map(|f| if f.is_finite() { *f } else { 0.0 }).collect::<Vec<f32>>(),
            "voiced_prob": f0.voiced_prob,
        },
        "notes": notes_with_fingering(&notes),
        "beats_s": beats.beats_s,
        "downbeats_s": beats.downbeats_s,
        "tempo_bpm": beats.tempo_bpm,
        "bow_changes_s": bow_changes_s,
        "arousal": {"rate_hz": 2, "values": arousal},
    });
    write_atomically(&args.output, |w| {
        serde_json::to_writer(w, &document).map_err(|e| e.to_string())
    })?;
    timing.push(("fingering + write", t.elapsed()));
    bar.inc(1);
    bar.finish_and_clear();

    let voiced = f0.f0_hz.iter().filter(|f| f.is_finite()).count();
    report.line(&format!(
        "{}: {:.1} s → {} notes, {:.0}% voiced, {:.1} bpm in {} ({} beats, {} downbeats) written to {}",
        args.input.display(),
        original.duration_s(),
        notes.len(),
        100.0 * voiced as f64 / f0.f0_hz.len().max(1) as f64,
        beats.tempo_bpm,
        if beats.meter.subdivisions == 3 {
            format!("{}/8", 3 * beats.meter.beats_per_bar)
        } else {
            format!("{}/4", beats.meter.beats_per_bar)
        },
        beats.beats_s.len(),
        beats.downbeats_s.len(),
        args.output.display()
    ));
    let total: Duration = timing.iter().map(|(_, d)| *d).sum();
    let parts: Vec<String> = timing
        .iter()
        .map(|(name, d)| format!("{name} {:.1} ms", d.as_secs_f64() * 1e3))
        .collect();
    report.line(&format!(
        "timing: {}, total {:.1} ms",
        parts.join(", "),
        total.as_secs_f64() * 1e3
    ));
    Ok(())
}

/// The notes as JSON objects, with string/position/finger from the optimal planner for
/// every note the fingerboard can play (planned together, in order).
fn notes_with_fingering(notes: &[Note]) -> Vec<Value> {
    let planner = OptimalPlanner::default();
    let playable: Vec<usize> = (0..notes.len())
        .filter(|&i| !planner.table().places(notes[i].midi).is_empty())
        .collect();
    let pitches: Vec<u8> = playable.iter().map(|&i| notes[i].midi).collect();
    let plan = planner.plan(&pitches).unwrap_or_default();
    let mut places = vec![None; notes.len()];
    for (&i, f) in playable.iter().zip(plan) {
        places[i] = Some(f);
    }
    notes
        .iter()
        .zip(places)
        .map(|(n, place)| {
            let mut o = Map::new();
            o.insert("onset_s".into(), json!(n.onset_s));
            o.insert("offset_s".into(), json!(n.offset_s));
            o.insert("midi".into(), json!(n.midi));
            if let Some(f) = place {
                o.insert("string".into(), json!(f.string.number()));
                o.insert("position".into(), json!(f.position));
                o.insert("finger".into(), json!(f.finger));
            }
            Value::Object(o)
        })
        .collect()
}
