//! End to end through the `violin-skeleton` binary: the demo, every output format read back,
//! and bad inputs (one clear line, exit code 1, no partial output).
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use violin_skeleton::{Motion, MotionFormat};

fn bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_violin-skeleton"))
}

fn run(args: &[&str], cwd: &Path) -> Output {
    Command::new(bin())
        .args(args)
        .current_dir(cwd)
        .output()
        .unwrap()
}

fn write_wav(path: &Path, samples: &[f32], rate: u32) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for s in samples {
        w.write_sample((s * 20_000.0) as i16).unwrap();
    }
    w.finalize().unwrap();
}

fn assert_one_line_failure(out: &Output, what: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{what}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{what}: {err}");
    assert!(err.starts_with("error: "), "{what}: {err}");
}

#[test]
fn demo_writes_every_output_and_they_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(&["demo"], dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let demo = dir.path().join("demo-out");
    for f in [
        "demo.wav",
        "analysis.json",
        "motion.json",
        "motion.bvh",
        "preview.gif",
        "player.html",
    ] {
        assert!(demo.join(f).is_file(), "missing {f}");
    }
    let motion = Motion::read(demo.join("motion.json"), MotionFormat::Json).unwrap();
    assert!(
        (motion.duration_s() - 24.6).abs() < 1.5,
        "{}",
        motion.duration_s()
    );
    assert!(motion.frames().iter().all(|v| v.is_finite()));
    assert!(motion.max_bone_length_cv() < 0.005);
    let openpose = Motion::read(demo.join("openpose"), MotionFormat::OpenPose).unwrap();
    assert_eq!(openpose.len(), motion.len());
    // The analysis found the clip's bow changes (the Minuet has 48 strokes).
    let analysis: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(demo.join("analysis.json")).unwrap())
            .unwrap();
    let changes = analysis["bow_changes_s"].as_array().unwrap().len();
    assert!((30..=70).contains(&changes), "{changes} bow changes");
    // Every format through `generate`, read back.
    let wav = demo.join("demo.wav");
    for (name, fmt) in [
        ("m.json", MotionFormat::Json),
        ("m.csv", MotionFormat::Csv),
        ("m.npy", MotionFormat::Npy),
    ] {
        let path = dir.path().join(name);
        let st = run(
            &[
                "--quiet",
                "generate",
                wav.to_str().unwrap(),
                "-o",
                path.to_str().unwrap(),
            ],
            dir.path(),
        );
        assert!(
            st.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&st.stderr)
        );
        let m = Motion::read(&path, fmt).unwrap();
        assert_eq!(m.len(), motion.len(), "{name}");
    }
}

#[test]
fn bad_inputs_fail_cleanly_and_leave_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = d.join("notes.wav");
    std::fs::write(&text, "this is not audio\n".repeat(40)).unwrap();
    let silent = d.join("silent.wav");
    write_wav(&silent, &vec![0.0; 22_050 * 3], 22_050);
    let short = d.join("short.wav");
    let tone: Vec<f32> = (0..2205).map(|i| (i as f32 * 0.125).sin() * 0.5).collect();
    write_wav(&short, &tone, 22_050);
    let corrupt = d.join("corrupt.mp3");
    let mut bytes = vec![0xFFu8, 0xFB, 0x90, 0x64];
    bytes.extend((0..4000u32).map(|i| (i.wrapping_mul(2_654_435_761) >> 24) as u8));
    std::fs::write(&corrupt, bytes).unwrap();
    let out = d.join("out.json");
    for (input, what) in [
        (d.join("missing.wav"), "missing file"),
        (text, "not audio"),
        (silent, "silent file"),
        (short, "0.1 s file"),
        (corrupt, "corrupt mp3"),
    ] {
        let st = run(
            &[
                "generate",
                input.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ],
            d,
        );
        assert_one_line_failure(&st, what);
        assert!(!out.exists(), "{what}: partial output left");
    }
    // A folder as input is batch mode, whose -o is a folder: a file name is a usage error.
    let st = run(
        &["generate", d.to_str().unwrap(), "-o", out.to_str().unwrap()],
        d,
    );
    let err = String::from_utf8_lossy(&st.stderr);
    assert_eq!(st.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(!out.exists());
    // Unwritable output path.
    let wav = d.join("tone.wav");
    write_wav(&wav, &tone, 22_050);
    let st = run(
        &[
            "generate",
            wav.to_str().unwrap(),
            "-o",
            "/proc/no/such/dir/out.json",
        ],
        d,
    );
    assert_one_line_failure(&st, "unwritable output");
    let leftovers: Vec<_> = std::fs::read_dir(d)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn evaluate_on_a_folder_without_labels_fails_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report.json");
    let out = run(
        &[
            "evaluate",
            "--data",
            dir.path().to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ],
        dir.path(),
    );
    assert_one_line_failure(&out, "evaluate on an empty folder");
    assert!(String::from_utf8_lossy(&out.stderr).contains("neither a corpus"));
    assert!(!report.exists());
    let out = run(&["evaluate", "--data", "/no/such/folder"], dir.path());
    assert_one_line_failure(&out, "evaluate on a missing folder");
}
