//! `violin-skeleton render` end to end: GIF, HTML with audio, PNG frames, OpenPose, bad inputs.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::Command;

use violin_skeleton::motion_synth::{synthesize, SynthConfig};
use violin_skeleton::skeleton::MotionFormat;
use violin_skeleton::Performance;

fn cli() -> Command {
    Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
}

fn write_motion(path: &Path) {
    let perf = Performance::builder(2.0)
        .note(0.0, 1.0, 67)
        .note(1.0, 2.0, 74)
        .bow_changes(vec![1.0])
        .build()
        .unwrap();
    let motion = synthesize(&perf, &SynthConfig::default()).unwrap();
    motion.write(path, MotionFormat::Json).unwrap();
}

fn write_wav(path: &Path) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 8000,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for i in 0..16_000 {
        w.write_sample(((i as f32 * 0.3).sin() * 8000.0) as i16)
            .unwrap();
    }
    w.finalize().unwrap();
}

#[test]
fn renders_gif_html_and_png_frames() {
    let dir = tempfile::tempdir().unwrap();
    let motion = dir.path().join("motion.json");
    write_motion(&motion);

    let gif = dir.path().join("p.gif");
    let out = cli()
        .arg("render")
        .arg(&motion)
        .arg("-o")
        .arg(&gif)
        .args(["--width", "200", "--height", "120"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&gif).unwrap();
    assert_eq!(&bytes[..6], b"GIF89a");
    assert_eq!(u16::from_le_bytes([bytes[6], bytes[7]]), 200);
    assert_eq!(u16::from_le_bytes([bytes[8], bytes[9]]), 120);
    assert!(String::from_utf8_lossy(&out.stderr).contains("30 pictures"));

    let wav = dir.path().join("take.wav");
    write_wav(&wav);
    let html = dir.path().join("p.html");
    let out = cli()
        .arg("render")
        .arg(&motion)
        .arg("--audio")
        .arg(&wav)
        .arg("-o")
        .arg(&html)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains("data:audio/wav;base64,UklGR"));
    assert!(page.contains("\"fps\":30"));

    let frames = dir.path().join("frames");
    let out = cli()
        .arg("render")
        .arg(&motion)
        .arg("-o")
        .arg(&frames)
        .args(["--fps", "5", "-q"])
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(out.stderr.is_empty(), "--quiet prints nothing");
    assert_eq!(std::fs::read_dir(&frames).unwrap().count(), 10);
}

#[test]
fn bad_inputs_give_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let motion = dir.path().join("motion.json");
    write_motion(&motion);
    let run = |args: &[&str]| {
        let out = cli().arg("render").args(args).output().unwrap();
        (
            out.status.code().unwrap(),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let m = motion.to_str().unwrap();
    let gif = dir.path().join("x.gif");
    let (code, err) = run(&[m, "--audio", m, "-o", gif.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.starts_with("error: --audio"));
    let (code, err) = run(&["missing.json", "-o", gif.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(
        err.contains("missing.json") && err.lines().count() == 1,
        "{err}"
    );
    std::fs::write(
        dir.path().join("broken.json"),
        "{\"fps\": 30, \"frames\": [",
    )
    .unwrap();
    let broken = dir.path().join("broken.json");
    let (code, err) = run(&[broken.to_str().unwrap(), "-o", gif.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains("broken.json"), "{err}");
    assert!(!gif.exists(), "no output on failure");
    let (code, _) = run(&[m, "-o", dir.path().join("x.mkv").to_str().unwrap()]);
    assert_eq!(code, 2);
    // A bad flag value is a usage error (exit 2).
    let (code, err) = run(&[m, "--width", "0", "-o", gif.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn openpose_frames_fitted_to_the_canvas_as_generate_writes_them() {
    use violin_skeleton::skeleton::canvas::{Canvas, DEFAULT_CANVAS_MARGIN};
    use violin_skeleton::skeleton::formats::OpenPoseOptions;
    use violin_skeleton::skeleton::Motion;

    let dir = tempfile::tempdir().unwrap();
    let motion_path = dir.path().join("motion.json");
    write_motion(&motion_path);
    let poses = dir.path().join("cli").join("poses");
    std::fs::create_dir_all(dir.path().join("cli")).unwrap();
    std::fs::create_dir_all(dir.path().join("lib")).unwrap();
    let out = cli()
        .arg("render")
        .arg(&motion_path)
        .args(["--openpose", "--canvas", "640x640", "-o"])
        .arg(&poses)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The same frames as the library writes for a canvas-fitted motion (what generate does).
    let expected = dir.path().join("lib").join("poses");
    let motion = Motion::read(&motion_path, MotionFormat::Json).unwrap();
    let canvas: Canvas = "640x640".parse().unwrap();
    motion
        .fitted_to_canvas(canvas, DEFAULT_CANVAS_MARGIN)
        .write_openpose(&expected, &OpenPoseOptions::named_after(&expected))
        .unwrap();
    let mut names: Vec<_> = std::fs::read_dir(&expected)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    names.sort();
    assert_eq!(names.len(), motion.len());
    for name in &names {
        assert_eq!(
            std::fs::read(poses.join(name)).unwrap(),
            std::fs::read(expected.join(name)).unwrap(),
            "{name:?}"
        );
    }
    let first = std::fs::read_to_string(poses.join(&names[0])).unwrap();
    assert!(first.contains("hand_left_keypoints_2d") && first.contains("pose_keypoints_2d"));

    // A file output or a bad canvas is a usage error (exit 2) with one line.
    for args in [
        vec!["--openpose", "-o", "x.gif"],
        vec!["--openpose", "--canvas", "0x0", "-o", "p"],
        vec!["--openpose", "--canvas", "abc", "-o", "p"],
    ] {
        let out = cli()
            .current_dir(dir.path())
            .arg("render")
            .arg(&motion_path)
            .args(&args)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr).lines().count(),
            1,
            "{args:?}"
        );
    }
}
