//! `--time-signature` and `--tempo-bpm`: the analysis follows them, and hints that cannot be
//! used are refused with one line.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::{Command, Output};

mod common;

use common::{write_midi, write_samples_wav};
use corpus::item::clean_etude;
use serde_json::Value;

fn analyze(input: &Path, out: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
        .arg("analyze")
        .arg(input)
        .arg("-o")
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

fn refused(out: &Output, needle: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "accepted: {stderr}");
    assert!(stderr.contains(needle), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn the_analysis_follows_the_hints() {
    let dir = tempfile::tempdir().unwrap();
    let item = clean_etude(6, 14.0, (110.0, 110.0)).unwrap();
    let wav = dir.path().join("violin.wav");
    write_samples_wav(&wav, &item.audio, 22_050);
    let read = |extra: &[&str]| -> Value {
        let out = dir.path().join("a.json");
        let st = analyze(&wav, &out, extra);
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap()
    };
    for (ts, beats, subdivisions) in [("3/4", 3, 2), ("4/4", 4, 2), ("6/8", 2, 3)] {
        let a = read(&["--time-signature", ts, "--tempo-bpm", "110"]);
        assert_eq!(a["meter"]["beats_per_bar"], beats, "{ts}");
        assert_eq!(a["meter"]["subdivisions"], subdivisions, "{ts}");
        let tempo = a["tempo_bpm"].as_f64().unwrap();
        assert!(
            (110.0 / 1.15..=110.0 * 1.15).contains(&tempo),
            "{ts}: {tempo}"
        );
        let beats_s = a["beats_s"].as_array().unwrap().len();
        let downbeats_s = a["downbeats_s"].as_array().unwrap().len();
        assert!(beats_s >= 15, "{ts}: {beats_s} beats");
        // Every bar of the given length: downbeats ≈ beats / beats per bar.
        let bars = beats_s as f64 / f64::from(beats);
        assert!(
            (downbeats_s as f64 - bars).abs() <= 2.0,
            "{ts}: {downbeats_s} of {beats_s}"
        );
    }
    // A tempo range an octave away moves the beats there.
    let slow = read(&["--tempo-bpm", "50-62"]);
    let tempo = slow["tempo_bpm"].as_f64().unwrap();
    assert!((50.0..=62.0).contains(&tempo), "{tempo}");
}

#[test]
fn hints_that_cannot_be_used_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let item = clean_etude(6, 4.0, (110.0, 110.0)).unwrap();
    let wav = dir.path().join("violin.wav");
    write_samples_wav(&wav, &item.audio, 22_050);
    let out = dir.path().join("a.json");
    refused(
        &analyze(&wav, &out, &["--time-signature", "3/5"]),
        "not a time signature",
    );
    refused(
        &analyze(&wav, &out, &["--time-signature", "13/4"]),
        "at most 12 beats per bar",
    );
    refused(
        &analyze(&wav, &out, &["--tempo-bpm", "80-60"]),
        "not a tempo",
    );
    refused(
        &analyze(
            &wav,
            &out,
            &["--beats", "classic", "--time-signature", "3/4"],
        ),
        "learned beat tracker",
    );
    let mid = dir.path().join("scale.mid");
    write_midi(&mid, 16);
    let midi_refused = analyze(&mid, &out, &["--tempo-bpm", "120"]);
    refused(&midi_refused, "apply to audio");
    refused(&midi_refused, "scale.mid");
    let gru = Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
        .args([
            "generate",
            "--method",
            "gru",
            "--time-signature",
            "3/4",
            "-o",
        ])
        .arg(dir.path().join("m.json"))
        .arg(&wav)
        .output()
        .unwrap();
    refused(&gru, "does not track beats");
    assert!(!out.exists(), "a refused run wrote its output");
}
