//! `violin-skeleton analyze` end to end: the analysis.json schema on synthetic violin (a
//! corpus étude rendered by the corpus's bowed-string synthesizer), short and silent audio,
//! bad inputs.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::Command;

mod common;

use common::write_samples_wav as write_wav;
use corpus::item::clean_etude;
use serde_json::Value;

fn cli() -> Command {
    Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
}

fn analyze(wav: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    cli()
        .arg("analyze")
        .arg(wav)
        .arg("-o")
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn synthetic_violin_gives_the_schema() {
    let dir = tempfile::tempdir().unwrap();
    let item = clean_etude(6, 14.0, (110.0, 110.0)).unwrap();
    let duration_s = item.audio.len() as f64 / 22_050.0;
    let wav = dir.path().join("violin.wav");
    write_wav(&wav, &item.audio, 22_050);
    let out = dir.path().join("analysis.json");
    let st = analyze(&wav, &out, &[]);
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let stderr = String::from_utf8_lossy(&st.stderr);
    assert!(stderr.contains("timing:"), "{stderr}");
    let a: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert!((a["duration_s"].as_f64().unwrap() - duration_s).abs() < 0.01);
    assert_eq!(a["sample_rate"], 22_050);
    let hz = a["f0"]["hz"].as_array().unwrap();
    assert_eq!(hz.len(), a["f0"]["voiced_prob"].as_array().unwrap().len());
    assert!(hz.iter().all(|v| v.as_f64().unwrap() >= 0.0));
    assert!(hz.iter().any(|v| v.as_f64().unwrap() == 0.0)); // the silent tail
    let notes = a["notes"].as_array().unwrap();
    assert!(
        notes.len() >= item.timeline.notes.len() * 8 / 10,
        "{} notes of {}",
        notes.len(),
        item.timeline.notes.len()
    );
    for n in notes {
        let string = n["string"].as_u64().unwrap();
        assert!((1..=4).contains(&string));
        assert!(n["finger"].as_u64().unwrap() <= 4);
        assert!(n["offset_s"].as_f64().unwrap() > n["onset_s"].as_f64().unwrap());
    }
    // Strokes: one per bow change, each with a direction and a string.
    let strokes = a["bow_strokes"].as_array().unwrap();
    assert_eq!(strokes.len(), a["bow_changes_s"].as_array().unwrap().len());
    assert!(!strokes.is_empty());
    for s in strokes {
        assert!((1..=4).contains(&s["string"].as_u64().unwrap()), "{s}");
        assert!(
            ["down", "up"].contains(&s["direction"].as_str().unwrap()),
            "{s}"
        );
    }
    let beats = a["beats_s"].as_array().unwrap();
    assert!(beats.len() >= 20, "{} beats", beats.len());
    assert!(!a["downbeats_s"].as_array().unwrap().is_empty());
    println!(
        "{} notes of {}, {} beats of {}, {} bpm ({} at 110 bpm)",
        notes.len(),
        item.timeline.notes.len(),
        beats.len(),
        item.timeline.beats_s.len(),
        a["tempo_bpm"],
        item.time_signature
    );
    assert!((a["tempo_bpm"].as_f64().unwrap() - 110.0).abs() < 8.0);

    let out30 = dir.path().join("a30.json");
    let st = analyze(&wav, &out30, &["--f0-fps", "30"]);
    assert!(st.status.success());
    let a30: Value = serde_json::from_str(&std::fs::read_to_string(&out30).unwrap()).unwrap();
    assert!((a30["f0"]["hop_s"].as_f64().unwrap() - 1.0 / 30.0).abs() < 1e-12);
}

#[test]
fn short_and_silent_audio_do_not_fail() {
    let dir = tempfile::tempdir().unwrap();
    for (name, samples) in [
        (
            "short.wav",
            (0..2_205)
                .map(|i| (i as f32 * 0.1).sin() * 0.5)
                .collect::<Vec<_>>(),
        ),
        ("silent.wav", vec![0.0f32; 22_050]),
        // One bowed-like note (50 ms attack) between silences, and 2 s of one tone: no
        // pulse, so no tempo may be invented.
        ("one_note.wav", one_note(1.0, 1.5, 1.0)),
        ("two_s_tone.wav", one_note(0.0, 2.0, 0.0)),
        // 8 s of white noise at about −20 dBFS: no beats and no bow strokes either.
        ("noise.wav", noise(8.0)),
    ] {
        let wav = dir.path().join(name);
        write_wav(&wav, &samples, 22_050);
        // Both beat trackers.
        for beats in ["learned", "classic"] {
            let out = dir.path().join(format!("{name}.{beats}.json"));
            let st = analyze(&wav, &out, &["--quiet", "--beats", beats]);
            assert!(
                st.status.success(),
                "{name}: {}",
                String::from_utf8_lossy(&st.stderr)
            );
            assert!(st.stderr.is_empty());
            let a: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
            assert!(
                a["beats_s"].as_array().unwrap().is_empty(),
                "{name} {beats}"
            );
            assert_eq!(a["tempo_bpm"].as_f64(), Some(0.0), "{name} {beats}");
            assert!(a.get("meter").is_none_or(Value::is_null), "{name} {beats}");
            let confidence = a["beat_confidence"].as_f64().unwrap_or(0.0);
            assert!(confidence < 0.1, "{name} {beats}: confidence {confidence}");
            if name == "noise.wav" || name == "silent.wav" {
                assert!(a["bow_changes_s"].as_array().unwrap().is_empty(), "{name}");
                assert!(a["bow_strokes"].as_array().unwrap().is_empty(), "{name}");
            }
        }
    }
}

/// `seconds` of seeded white noise, RMS about 0.1 (−20 dBFS).
fn noise(seconds: f32) -> Vec<f32> {
    let mut x = 0x2545_f491_4f6c_dd1du64;
    (0..(seconds * 22_050.0) as usize)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            ((x >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 0.35
        })
        .collect()
}

/// `before_s` of silence, a 440 Hz note of `note_s` (50 ms attack), `after_s` of silence.
fn one_note(before_s: f32, note_s: f32, after_s: f32) -> Vec<f32> {
    let sr = 22_050.0f32;
    let n = |s: f32| (s * sr) as usize;
    let mut out = vec![0.0f32; n(before_s)];
    out.extend((0..n(note_s)).map(|i| {
        let t = i as f32 / sr;
        0.3 * (t / 0.05).min(1.0) * (std::f32::consts::TAU * 440.0 * t).sin()
    }));
    out.extend(vec![0.0f32; n(after_s)]);
    out
}

#[test]
fn bad_inputs_fail_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.json");
    let st = analyze(&dir.path().join("missing.wav"), &out, &[]);
    assert_eq!(st.status.code(), Some(1));
    let err = String::from_utf8_lossy(&st.stderr);
    assert!(
        err.starts_with("error:") && err.contains("missing.wav"),
        "{err}"
    );
    assert!(!out.exists());

    let junk = dir.path().join("junk.wav");
    std::fs::write(&junk, b"RIFF1234WAVEjunkjunk").unwrap();
    let st = analyze(&junk, &out, &[]);
    assert_eq!(st.status.code(), Some(1));
    assert!(!out.exists());

    let wav = dir.path().join("ok.wav");
    write_wav(&wav, &[0.1; 4410], 22_050);
    let st = analyze(&wav, &out, &["--f0-fps", "0"]);
    assert_eq!(st.status.code(), Some(2));
}

#[test]
fn weight_flags_load_the_given_files() {
    let dir = tempfile::tempdir().unwrap();
    let wav = dir.path().join("ok.wav");
    let tone: Vec<f32> = (0..44_100)
        .map(|i| 0.3 * (2.0 * std::f32::consts::PI * 440.0 * i as f32 / 22_050.0).sin())
        .collect();
    write_wav(&wav, &tone, 22_050);
    let out = dir.path().join("a.json");

    // Each embedded bowing model, given as a file, gives the result of choosing it.
    let weights_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../bowing-net/weights");
    let mut w = String::new();
    for (file, net) in [
        ("bowing-net.safetensors", "cnn"),
        ("stroke-net.safetensors", "strokes"),
    ] {
        let weights = dir.path().join(file);
        std::fs::copy(weights_dir.join(file), &weights).unwrap();
        let st = analyze(&wav, &out, &["--quiet", "--bowing-net", net]);
        assert!(st.status.success());
        let chosen: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        w = weights.to_str().unwrap().to_string();
        let st = analyze(&wav, &out, &["--quiet", "--bowing-weights", &w]);
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
        let given: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        assert_eq!(given["bow_changes_s"], chosen["bow_changes_s"], "{net}");
        assert_eq!(given["bow_strokes"], chosen["bow_strokes"], "{net}");
    }
    let w = w.as_str();

    // A file that is not emotion-net weights is one readable error naming it.
    refused_naming(
        &wav,
        &out,
        &["--emotion-weights", w],
        "stroke-net.safetensors",
    );
}

/// `analyze WAV -o OUT ARGS…` fails with one `error:` line naming `name` once, and writes
/// nothing.
fn refused_naming(wav: &Path, out: &Path, args: &[&str], name: &str) {
    if out.exists() {
        std::fs::remove_file(out).unwrap();
    }
    let st = analyze(wav, out, args);
    assert_eq!(st.status.code(), Some(1));
    let err = String::from_utf8_lossy(&st.stderr);
    assert!(
        err.starts_with("error:") && err.matches(name).count() == 1 && err.lines().count() == 1,
        "{err}"
    );
    assert!(!out.exists());
}

/// A 12 s corpus étude (seed `seed`, `bpm` throughout) written as `DIR/etude.wav`.
fn etude_wav(dir: &Path, seed: u64, bpm: f64) -> std::path::PathBuf {
    let item = clean_etude(seed, 12.0, (bpm, bpm)).unwrap();
    let wav = dir.join("etude.wav");
    write_wav(&wav, &item.audio, 22_050);
    wav
}

#[test]
fn stroke_weights_flag_replaces_the_embedded_stroke_network() {
    let dir = tempfile::tempdir().unwrap();
    let wav = etude_wav(dir.path(), 5, 110.0);
    let out = dir.path().join("a.json");
    let weights_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../bowing-net/weights");
    let strokes = dir.path().join("stroke-net.safetensors");
    std::fs::copy(weights_dir.join("stroke-net.safetensors"), &strokes).unwrap();
    let cnn = dir.path().join("bowing-net.safetensors");
    std::fs::copy(weights_dir.join("bowing-net.safetensors"), &cnn).unwrap();
    let (strokes, cnn) = (strokes.to_str().unwrap(), cnn.to_str().unwrap());
    let read = |out: &Path| -> Value {
        serde_json::from_str(&std::fs::read_to_string(out).unwrap()).unwrap()
    };

    // The shipped stroke network given as a file, inside each model that has one, gives
    // that model's result: the default ensemble, and the stroke network alone.
    for net in ["ensemble", "strokes"] {
        let st = analyze(&wav, &out, &["--quiet", "--bowing-net", net]);
        assert!(st.status.success());
        let embedded = read(&out);
        assert!(!embedded["bow_changes_s"].as_array().unwrap().is_empty());
        let st = analyze(
            &wav,
            &out,
            &["--quiet", "--bowing-net", net, "--stroke-weights", strokes],
        );
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
        let given = read(&out);
        assert_eq!(given["bow_changes_s"], embedded["bow_changes_s"], "{net}");
        assert_eq!(given["bow_strokes"], embedded["bow_strokes"], "{net}");
    }

    // A CNN file, or the CNN alone chosen, is one readable error naming the file.
    refused_naming(
        &wav,
        &out,
        &["--stroke-weights", cnn],
        "bowing-net.safetensors",
    );
    refused_naming(
        &wav,
        &out,
        &["--bowing-net", "cnn", "--stroke-weights", strokes],
        "stroke-net.safetensors",
    );
    // It cannot be given with --bowing-weights (a usage error).
    let st = analyze(
        &wav,
        &out,
        &["--bowing-weights", strokes, "--stroke-weights", strokes],
    );
    assert_eq!(st.status.code(), Some(2));
}

#[test]
fn ensemble_cnn_weights_flag_replaces_the_embedded_ensemble_cnn() {
    let dir = tempfile::tempdir().unwrap();
    let wav = etude_wav(dir.path(), 6, 96.0);
    let out = dir.path().join("a.json");
    let weights_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../bowing-net/weights");
    let copy = |name: &str| {
        let p = dir.path().join(name);
        std::fs::copy(weights_dir.join(name), &p).unwrap();
        p.to_str().unwrap().to_string()
    };
    let (ens_cnn, strokes) = (
        copy("ensemble-cnn.safetensors"),
        copy("stroke-net.safetensors"),
    );
    let changes = |args: &[&str]| -> Value {
        let st = analyze(&wav, &out, args);
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
        let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        v["bow_changes_s"].clone()
    };
    // The embedded ensemble CNN given as a file (alone, and with the stroke network as a
    // file too) gives the default model's bow changes.
    let embedded = changes(&["--quiet"]);
    assert!(!embedded.as_array().unwrap().is_empty());
    assert_eq!(
        changes(&["--quiet", "--ensemble-cnn-weights", &ens_cnn]),
        embedded
    );
    assert_eq!(
        changes(&[
            "--quiet",
            "--ensemble-cnn-weights",
            &ens_cnn,
            "--stroke-weights",
            &strokes
        ]),
        embedded
    );
    // A stroke-network file, or a model without the ensemble, is one error naming the file.
    refused_naming(
        &wav,
        &out,
        &["--ensemble-cnn-weights", &strokes],
        "stroke-net.safetensors",
    );
    refused_naming(
        &wav,
        &out,
        &[
            "--bowing-net",
            "strokes",
            "--ensemble-cnn-weights",
            &ens_cnn,
        ],
        "ensemble-cnn.safetensors",
    );
    let st = analyze(
        &wav,
        &out,
        &[
            "--bowing-weights",
            &ens_cnn,
            "--ensemble-cnn-weights",
            &ens_cnn,
        ],
    );
    assert_eq!(st.status.code(), Some(2));
}

#[test]
fn beat_weights_flag_loads_the_given_file() {
    let dir = tempfile::tempdir().unwrap();
    let wav = etude_wav(dir.path(), 3, 100.0);
    let out = dir.path().join("a.json");
    let st = analyze(&wav, &out, &["--quiet"]);
    assert!(st.status.success());
    let embedded: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert!(
        embedded["beats_s"].as_array().is_some_and(|b| b.len() > 4),
        "{embedded}"
    );

    // The embedded beat-net, given as a file, gives the same beats and downbeats.
    let weights_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../beat-net/weights");
    let beat = dir.path().join("beat-net.safetensors");
    std::fs::copy(weights_dir.join("beat-net.safetensors"), &beat).unwrap();
    let st = analyze(
        &wav,
        &out,
        &["--quiet", "--beat-weights", beat.to_str().unwrap()],
    );
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let given: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(given["beats_s"], embedded["beats_s"]);
    assert_eq!(given["downbeats_s"], embedded["downbeats_s"]);

    // Another network's weights are refused with one line naming the file.
    let cnn = dir.path().join("bowing-cnn.safetensors");
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../bowing-net/weights/bowing-net.safetensors"),
        &cnn,
    )
    .unwrap();
    refused_naming(
        &wav,
        &out,
        &["--beat-weights", cnn.to_str().unwrap()],
        "bowing-cnn.safetensors",
    );
}
