//! Dumps, per audio file, every beat-level candidate `BeatTracker` considers (tempo, beats,
//! features, score), the winner's bar features (`BeatFeatures`, the metre step's input) and
//! what `track` returns, for `scripts/fit_beat_level.py` and `scripts/fit_meter.py`.
//!
//! ```sh
//! cargo run --release -p beat-track --example level_features -- OUT_DIR FILE...
//! cargo run --release -p beat-track --example level_features -- --print-default-config
//! ```
//! For the i-th `FILE` it writes `OUT_DIR/<i>.json`. Notes come from the default
//! `PitchTracker` and `segment_notes`, as in `Pipeline::analyze`; with
//! `LEVEL_WITHOUT_NOTES=1` the tracker gets none (detected onsets stand in for them).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use beat_track::{BarEvidence, BeatConfig, BeatFeatures, BeatTracker, OnsetStrength};
use pitch_track::{segment_notes, NoteConfig, PitchConfig, PitchTracker};
use rayon::prelude::*;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--print-default-config") {
        let cfg = serde_json::to_string_pretty(&BeatConfig::default()).expect("json");
        println!("{cfg}");
        return;
    }
    if args.len() < 2 {
        eprintln!("usage: level_features OUT_DIR FILE...");
        std::process::exit(2);
    }
    let out_dir = args.remove(0);
    std::fs::create_dir_all(&out_dir).expect("create output folder");
    let pitch = PitchTracker::new(PitchConfig::default()).expect("valid pitch config");
    // BEAT_CONFIG=file.json: a whole `BeatConfig` (serde JSON) instead of the default.
    let cfg: BeatConfig = match std::env::var_os("BEAT_CONFIG") {
        Some(path) => serde_json::from_str(&std::fs::read_to_string(path).expect("read config"))
            .expect("a BeatConfig in JSON"),
        None => BeatConfig::default(),
    };
    let beats = BeatTracker::new(cfg.clone()).expect("valid beat config");
    let onset = OnsetStrength::new(cfg.onset.clone()).expect("valid onset config");
    args.par_iter().enumerate().for_each(|(index, file)| {
        let audio = dsp_mel::load_audio(file).expect("decode");
        let audio = dsp_mel::resample(&audio, dsp_mel::DEFAULT_ANALYSIS_RATE_HZ).expect("resample");
        let (samples, rate) = (audio.samples(), audio.sample_rate_hz());
        let track = pitch.track(samples).expect("pitch");
        let notes = segment_notes(&track, samples, rate, &NoteConfig::default()).expect("notes");
        // LEVEL_WITHOUT_NOTES=1: what beat-track does on its own (onsets stand in for notes).
        let notes = (std::env::var_os("LEVEL_WITHOUT_NOTES").is_none()).then_some(&notes[..]);
        // BOW_CHANGES_DIR=dir: bow changes from dir/<i>.json (an `analyze` output's
        // `bow_changes_s`) as metre evidence.
        let bows: Option<Vec<f64>> = std::env::var_os("BOW_CHANGES_DIR").map(|dir| {
            let path = std::path::Path::new(&dir).join(format!("{index}.json"));
            let json: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(path).expect("read analysis"))
                    .expect("analysis JSON");
            json["bow_changes_s"]
                .as_array()
                .expect("bow_changes_s")
                .iter()
                .filter_map(serde_json::Value::as_f64)
                .collect()
        });
        let evidence = BarEvidence {
            notes,
            bow_changes_s: bows.as_deref(),
        };
        let candidates = beats
            .level_candidates_with(samples, evidence)
            .expect("candidates");
        let chosen = beats.track_with(samples, evidence).expect("beats");
        // The metre step's input: the winning candidate's beats and their bar features.
        let level = candidates
            .iter()
            .reduce(|best, c| if c.score > best.score { c } else { best });
        let bar_features = level.map(|c| {
            let env = onset.compute(samples).expect("onset strength");
            BeatFeatures::new(&c.beats_s, &env, evidence, &cfg.meter)
        });
        let json = serde_json::json!({
            "file": file,
            "candidates": candidates,
            "beats_s": chosen.beats_s,
            "downbeats_s": chosen.downbeats_s,
            "tempo_bpm": chosen.tempo_bpm,
            "onsets_s": chosen.onsets_s,
            "notes": notes.unwrap_or_default().iter().map(|n| [n.onset_s, n.offset_s, f64::from(n.midi)]).collect::<Vec<_>>(),
            "level_tempo_bpm": level.map(|c| c.tempo_bpm),
            "level_beats_s": level.map(|c| c.beats_s.clone()),
            "bar_features": bar_features,
        });
        let path = std::path::Path::new(&out_dir).join(format!("{index}.json"));
        std::fs::write(&path, serde_json::to_string(&json).expect("json")).expect("write json");
    });
}
