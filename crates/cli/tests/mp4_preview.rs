//! MP4 previews with the audio, checked with `ffprobe`: a video stream of the expected size
//! and frame count, and an audio stream when audio was given.
//!
//! Needs ffmpeg and ffprobe (Debian: `apt-get install ffmpeg`; `.ci/run` installs it and
//! sets `VIOLIN_SKELETON_REQUIRE_FFMPEG=1`, so there a missing ffmpeg fails the test).
//! Without that variable and without ffmpeg, the encoding checks are skipped with a note.
//! The one-line error for a missing ffmpeg is checked everywhere (through `FFMPEG`).
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::{write_midi, write_wav};
use serde_json::Value;

fn cli() -> Command {
    Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn have(program: &str) -> bool {
    Command::new(program)
        .arg("-version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// ffprobe's streams of `file`, counting the video frames.
fn streams(file: &Path) -> Vec<Value> {
    let out = Command::new("ffprobe")
        .args([
            "-v",
            "error",
            "-count_frames",
            "-show_streams",
            "-of",
            "json",
        ])
        .arg(file)
        .output()
        .unwrap();
    assert!(out.status.success(), "ffprobe failed on {}", file.display());
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    v["streams"].as_array().unwrap().clone()
}

fn stream<'a>(streams: &'a [Value], kind: &str) -> Option<&'a Value> {
    streams.iter().find(|s| s["codec_type"] == kind)
}

#[test]
fn mp4_previews_have_the_pictures_and_the_sound() {
    let dir = tempfile::tempdir().unwrap();
    let mid = dir.path().join("piece.mid");
    write_midi(&mid, 8); // 4 s
    let json = dir.path().join("m.json");
    let wav = dir.path().join("tone.wav");
    write_wav(&wav, 6.0);
    if !(have("ffmpeg") && have("ffprobe")) {
        assert!(
            std::env::var_os("VIOLIN_SKELETON_REQUIRE_FFMPEG").is_none(),
            "ffmpeg and ffprobe are required here but not found: apt-get install ffmpeg"
        );
        eprintln!("skipped MP4 encoding: no ffmpeg/ffprobe on PATH (apt-get install ffmpeg)");
        return;
    }
    // generate --preview P.mp4 from MIDI: a silent video at the motion's 30 fps, 640×360.
    let silent = dir.path().join("silent.mp4");
    ok(&cli()
        .args(["generate", "--quiet"])
        .arg(&mid)
        .arg("-o")
        .arg(&json)
        .arg("--preview")
        .arg(&silent)
        .output()
        .unwrap());
    let motion: Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let frames = motion["frames"].as_array().unwrap().len();
    let s = streams(&silent);
    let video = stream(&s, "video").expect("a video stream");
    assert_eq!(video["codec_name"], "h264");
    assert_eq!(
        (video["width"].as_u64(), video["height"].as_u64()),
        (Some(640), Some(360))
    );
    assert_eq!(video["pix_fmt"], "yuv420p");
    assert_eq!(
        video["nb_read_frames"]
            .as_str()
            .unwrap()
            .parse::<usize>()
            .unwrap(),
        frames
    );
    assert!(stream(&s, "audio").is_none(), "MIDI input: no audio stream");

    // render MOTION --audio WAV -o P.mp4: 6 s of audio, a shorter motion: cut to the motion.
    let video_path = dir.path().join("with_audio.mp4");
    ok(&cli()
        .args(["render", "--quiet", "--width", "320", "--height", "180"])
        .arg(&json)
        .arg("--audio")
        .arg(&wav)
        .arg("-o")
        .arg(&video_path)
        .output()
        .unwrap());
    let s = streams(&video_path);
    let video = stream(&s, "video").expect("a video stream");
    assert_eq!(
        (video["width"].as_u64(), video["height"].as_u64()),
        (Some(320), Some(180))
    );
    let n = video["nb_read_frames"]
        .as_str()
        .unwrap()
        .parse::<usize>()
        .unwrap();
    assert!(
        n.abs_diff(frames) <= 1,
        "{n} pictures for {frames} motion frames"
    );
    let audio = stream(&s, "audio").expect("an audio stream");
    assert_eq!(audio["codec_name"], "aac");
    let audio_s: f64 = audio["duration"].as_str().unwrap().parse().unwrap();
    assert!(
        (audio_s - frames as f64 / 30.0).abs() < 0.2,
        "audio {audio_s} s"
    );
    // No temporary left beside the outputs.
    let stray: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter(|n| n.contains(".tmp"))
        .collect();
    assert!(stray.is_empty(), "{stray:?}");

    // generate WAV --preview P.mp4: the recording's sound in the video.
    let from_audio = dir.path().join("from_audio.mp4");
    ok(&cli()
        .args(["generate", "--quiet"])
        .arg(&wav)
        .arg("-o")
        .arg(dir.path().join("tone.json"))
        .arg("--preview")
        .arg(&from_audio)
        .output()
        .unwrap());
    let s = streams(&from_audio);
    assert!(stream(&s, "video").is_some() && stream(&s, "audio").is_some());
}

#[test]
fn an_odd_mp4_size_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let mid = dir.path().join("piece.mid");
    write_midi(&mid, 2);
    let json = dir.path().join("m.json");
    ok(&cli()
        .args(["generate", "--quiet"])
        .arg(&mid)
        .arg("-o")
        .arg(&json)
        .output()
        .unwrap());
    let out = cli()
        .args(["render", "--width", "321"])
        .arg(&json)
        .arg("-o")
        .arg(dir.path().join("v.mp4"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("even"));
}

#[test]
fn a_missing_ffmpeg_is_one_line_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let mid = dir.path().join("piece.mid");
    write_midi(&mid, 2);
    let json = dir.path().join("m.json");
    let out = cli()
        .env("FFMPEG", dir.path().join("no-such-ffmpeg"))
        .arg("generate")
        .arg(&mid)
        .arg("-o")
        .arg(&json)
        .arg("--preview")
        .arg(dir.path().join("p.mp4"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("ffmpeg is not installed") && err.contains("apt-get install ffmpeg"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    // Checked before the motion was made: nothing written.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}
