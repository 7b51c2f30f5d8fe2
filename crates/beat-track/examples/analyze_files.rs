//! Analyses audio files with exactly the calls of `Pipeline::analyze` (default `PitchTracker`,
//! `segment_notes`, `BeatTracker` with the notes) and writes, per file, a JSON with the
//! results and the time of each stage — for `scripts/compare_analysis_librosa.py`, which
//! needs per-stage timings the `analyze` command does not print.
//!
//! ```sh
//! cargo run --release -p beat-track --example analyze_files -- OUT_DIR [--repeat N] FILE...
//! ```
//! For `FILE` = `a/b/audio.wav` it writes `OUT_DIR/<index>.json` (index = position in the
//! argument list) with `f0_hz` (0 = unvoiced), `f0_hop_s`, `notes`, `onsets_s`, `beats_s`,
//! `downbeats_s`, `tempo_bpm`, `meter` and `timing_s`: the best of N runs (default 1) of
//! `pitch` (pYIN), `notes` (segmentation), `beats` (the whole `BeatTracker::track`: onset
//! strength, onsets, tempo, beats, metre, downbeats) and `beats_only` (the same without
//! notes). Decoding and resampling to 22 050 Hz are done once beforehand and not timed
//! (`decode_s` and `resample_s` are reported separately), as librosa's calls are timed on
//! audio already loaded.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::time::Instant;

use beat_track::{BeatConfig, BeatTracker};
use pitch_track::{segment_notes, NoteConfig, PitchConfig, PitchTracker};

/// Best (minimum) wall time of `repeat` calls of `f`, and the last result.
fn best_of<T>(repeat: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..repeat.max(1) {
        let t0 = Instant::now();
        let r = f();
        best = best.min(t0.elapsed().as_secs_f64());
        out = Some(r);
    }
    (best, out.expect("at least one run"))
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    if args.is_empty() {
        eprintln!("usage: analyze_files OUT_DIR [--repeat N] FILE...");
        std::process::exit(2);
    }
    let out_dir = args.remove(0);
    let mut repeat = 1usize;
    if args.first().map(String::as_str) == Some("--repeat") {
        repeat = args
            .get(1)
            .expect("--repeat N")
            .parse()
            .expect("N is a number");
        args.drain(..2);
    }
    std::fs::create_dir_all(&out_dir).expect("create output folder");
    let pitch = PitchTracker::new(PitchConfig::default()).expect("valid pitch config");
    let beats = BeatTracker::new(BeatConfig::default()).expect("valid beat config");
    for (index, file) in args.iter().enumerate() {
        let t0 = Instant::now();
        let audio = dsp_mel::load_audio(file).expect("decode");
        let decode_s = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let audio = dsp_mel::resample(&audio, dsp_mel::DEFAULT_ANALYSIS_RATE_HZ).expect("resample");
        let resample_s = t1.elapsed().as_secs_f64();
        let (samples, rate) = (audio.samples(), audio.sample_rate_hz());
        let (pitch_s, track) = best_of(repeat, || pitch.track(samples).expect("pitch"));
        let (notes_s, notes) = best_of(repeat, || {
            segment_notes(&track, samples, rate, &NoteConfig::default()).expect("notes")
        });
        let (beats_s, analysis) = best_of(repeat, || {
            beats.track(samples, Some(&notes)).expect("beats")
        });
        let (beats_only_s, _) = best_of(repeat, || beats.track(samples, None).expect("beats"));
        let json = serde_json::json!({
            "file": file,
            "duration_s": samples.len() as f64 / f64::from(rate),
            "f0_hop_s": track.hop_s,
            "f0_hz": track.f0_hz.iter().map(|f| if f.is_finite() { *f } else { 0.0 }).collect::<Vec<_>>(),
            "notes": notes.iter().map(|n| serde_json::json!({
                "onset_s": n.onset_s, "offset_s": n.offset_s, "midi": n.midi
            })).collect::<Vec<_>>(),
            "onsets_s": analysis.onsets_s,
            "beats_s": analysis.beats_s,
            "downbeats_s": analysis.downbeats_s,
            "tempo_bpm": analysis.tempo_bpm,
            "meter": [analysis.meter.beats_per_bar, analysis.meter.subdivisions],
            "timing_s": {
                "decode": decode_s, "resample": resample_s, "pitch": pitch_s,
                "notes": notes_s, "beats": beats_s, "beats_only": beats_only_s,
            },
        });
        let path = Path::new(&out_dir).join(format!("{index}.json"));
        std::fs::write(&path, serde_json::to_string(&json).expect("json")).expect("write json");
        eprintln!(
            "{file}: pitch {:.1} ms, notes {:.1} ms, beats {:.1} ms (without notes {:.1} ms)",
            pitch_s * 1e3,
            notes_s * 1e3,
            beats_s * 1e3,
            beats_only_s * 1e3
        );
    }
}
