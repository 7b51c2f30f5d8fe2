//! `violin-skeleton features` end to end: output shape and bad inputs.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::Command;

use ndarray::Array2;
use ndarray_npy::read_npy;

fn cli() -> Command {
    Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
}

fn write_tone(path: &Path, rate: u32, seconds: f32) {
    let spec = hound::WavSpec {
        channels: 2,
        sample_rate: rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for i in 0..(rate as f32 * seconds) as usize {
        let s = (2.0 * std::f32::consts::PI * 440.0 * i as f32 / rate as f32).sin();
        let v = (s * 12_000.0) as i16;
        w.write_sample(v).unwrap();
        w.write_sample(v).unwrap();
    }
    w.finalize().unwrap();
}

#[test]
fn mel30_and_mel2_have_the_spec_shapes() {
    let dir = tempfile::tempdir().unwrap();
    let wav = dir.path().join("tone.wav");
    write_tone(&wav, 44_100, 3.0);
    let out30 = dir.path().join("m30.npy");
    let st = cli()
        .args(["features", wav.to_str().unwrap(), "--kind", "mel30", "-o"])
        .arg(&out30)
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let m: Array2<f32> = read_npy(&out30).unwrap();
    assert_eq!(m.dim(), (91, 128)); // 1 + 3 s · 22 050 / 735
    assert!(m.iter().all(|v| v.is_finite() && *v <= 100.0));

    let out2 = dir.path().join("m2.npy");
    let st = cli()
        .args([
            "--quiet",
            "features",
            wav.to_str().unwrap(),
            "--kind",
            "mel2",
        ])
        .args(["--scale", "power", "--sample-rate", "native", "-o"])
        .arg(&out2)
        .output()
        .unwrap();
    assert!(st.status.success());
    assert!(st.stderr.is_empty(), "--quiet printed something");
    let m: Array2<f32> = read_npy(&out2).unwrap();
    assert_eq!(m.dim(), (7, 64)); // 91 frames at 30 fps pooled by 15
    assert!(m.iter().all(|v| *v >= 0.0));
}

#[test]
fn bad_inputs_give_one_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let text = dir.path().join("notes.wav");
    std::fs::write(&text, "not audio\n".repeat(100)).unwrap();
    let empty = dir.path().join("empty.wav");
    std::fs::write(&empty, b"").unwrap();
    let missing = dir.path().join("missing.wav");
    let out = dir.path().join("out.npy");
    for input in [&text, &empty, &missing, &dir.path().to_path_buf()] {
        let st = cli()
            .args(["features", input.to_str().unwrap(), "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(st.status.code(), Some(1), "{input:?}");
        let err = String::from_utf8_lossy(&st.stderr);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.starts_with("error: "), "{err}");
        assert!(!out.exists());
    }
    // Unwritable output: the folder does not exist.
    let wav = dir.path().join("tone.wav");
    write_tone(&wav, 22_050, 0.5);
    let st = cli()
        .args(["features", wav.to_str().unwrap(), "-o"])
        .arg(dir.path().join("no/such/dir/out.npy"))
        .output()
        .unwrap();
    assert_eq!(st.status.code(), Some(1));
    // Bad flag value is a usage error.
    let st = cli()
        .args([
            "features",
            wav.to_str().unwrap(),
            "--sample-rate",
            "fast",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(st.status.code(), Some(2));
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left behind");
}
