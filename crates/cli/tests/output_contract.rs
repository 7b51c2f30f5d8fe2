//! The output contract (README): an output that is an input is refused before anything is
//! written, however it is spelled; `-` is standard output for single-file formats and
//! refused for folders; special files are written directly, never replaced; bad flag values
//! exit 2 before any work; the HTML player stays small and has sound for every input.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::process::{Command, Output};

use common::{write_midi, write_wav};

fn cli() -> Command {
    Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
}

fn run(args: &[&std::ffi::OsStr]) -> Output {
    cli().args(args).output().unwrap()
}

fn os<S: AsRef<std::ffi::OsStr> + ?Sized>(s: &S) -> &std::ffi::OsStr {
    s.as_ref()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A usage error: exit 2, one line on stderr that names `what`.
fn assert_usage(out: &Output, what: &str) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains(what), "expected {what:?} in {err}");
}

#[test]
fn an_output_that_is_an_input_is_refused_however_it_is_spelled() {
    let dir = tempfile::tempdir().unwrap();
    let wav = dir.path().join("rec.wav");
    write_wav(&wav, 2.0);
    let before = std::fs::read(&wav).unwrap();
    let link = dir.path().join("link.json");
    std::os::unix::fs::symlink(&wav, &link).unwrap();
    let hard = dir.path().join("hard.json");
    std::fs::hard_link(&wav, &hard).unwrap();
    let dotted = dir.path().join(".").join("rec.wav");
    for out in [&wav, &link, &hard, &dotted] {
        let r = run(&[
            os("generate"),
            wav.as_os_str(),
            os("-o"),
            out.as_os_str(),
            os("--format"),
            os("json"),
        ]);
        assert_usage(&r, "destroy the input");
    }
    let r = run(&[os("analyze"), wav.as_os_str(), os("-o"), link.as_os_str()]);
    assert_usage(&r, "destroy the input");
    let r = run(&[os("features"), wav.as_os_str(), os("-o"), hard.as_os_str()]);
    assert_usage(&r, "destroy the input");
    let preview = dir.path().join("p.html");
    let r = run(&[
        os("generate"),
        wav.as_os_str(),
        os("-o"),
        preview.as_os_str(),
        os("--format"),
        os("json"),
        os("--preview"),
        preview.as_os_str(),
    ]);
    assert_usage(&r, "also the output of -o");
    assert_eq!(
        std::fs::read(&wav).unwrap(),
        before,
        "the recording is intact"
    );
    assert!(!preview.exists());
}

#[test]
fn standard_output_takes_single_files_and_refuses_folders() {
    let dir = tempfile::tempdir().unwrap();
    let mid = dir.path().join("piece.mid");
    write_midi(&mid, 16);
    let r = cli()
        .args([
            os("--quiet"),
            os("generate"),
            mid.as_os_str(),
            os("-o"),
            os("-"),
            os("--format"),
            os("json"),
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", stderr(&r));
    let motion: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert!(motion.get("fps").is_some(), "motion JSON on stdout");

    // No format given: `-` would be an OpenPose folder, which stdout cannot hold.
    let r = cli()
        .args([os("generate"), mid.as_os_str(), os("-o"), os("-")])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_usage(&r, "cannot go to standard output");
    let motion = dir.path().join("m.json");
    let r = run(&[
        os("generate"),
        mid.as_os_str(),
        os("-o"),
        motion.as_os_str(),
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    let r = cli()
        .args([os("render"), motion.as_os_str(), os("-o"), os("-")])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_usage(&r, "cannot go to standard output");
    assert!(!dir.path().join("-").exists(), "no folder named -");
}

#[test]
fn special_files_are_written_directly_and_stay_special() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let mid = dir.path().join("piece.mid");
    write_midi(&mid, 16);
    let r = run(&[
        os("generate"),
        mid.as_os_str(),
        os("-o"),
        os("/dev/null"),
        os("--format"),
        os("csv"),
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());

    let fifo = dir.path().join("motion.csv");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let r = run(&[os("generate"), mid.as_os_str(), os("-o"), fifo.as_os_str()]);
    assert!(r.status.success(), "{}", stderr(&r));
    let text = reader.join().unwrap();
    assert!(
        text.starts_with("frame,") || text.contains("nose"),
        "CSV came through the FIFO"
    );
    assert!(
        std::fs::metadata(&fifo).unwrap().file_type().is_fifo(),
        "still a FIFO"
    );
}

#[test]
fn bad_flag_values_exit_2_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let mid = dir.path().join("piece.mid");
    write_midi(&mid, 16);
    let motion = dir.path().join("m.json");
    assert!(run(&[
        os("generate"),
        mid.as_os_str(),
        os("-o"),
        motion.as_os_str()
    ])
    .status
    .success());
    let gif = dir.path().join("p.gif");
    for (flag, value) in [("--fps", "0"), ("--width", "0"), ("--fps", "NaN")] {
        let r = run(&[
            os("render"),
            motion.as_os_str(),
            os("-o"),
            gif.as_os_str(),
            os(flag),
            os(value),
        ]);
        assert_usage(&r, flag);
    }
    let out = dir.path().join("out.json");
    let bad_preview = dir.path().join("p.txt");
    let r = run(&[
        os("generate"),
        mid.as_os_str(),
        os("-o"),
        out.as_os_str(),
        os("--preview"),
        bad_preview.as_os_str(),
    ]);
    assert_usage(&r, "--preview");
    let bvh = dir.path().join("m.bvh");
    let wav = dir.path().join("rec.wav");
    write_wav(&wav, 2.0);
    let r = run(&[
        os("generate"),
        wav.as_os_str(),
        os("-o"),
        bvh.as_os_str(),
        os("--method"),
        os("gru"),
    ]);
    assert_usage(&r, "BVH needs the 3-D rig");
    assert!(
        !out.exists() && !bvh.exists() && !gif.exists(),
        "nothing written"
    );
}

#[test]
fn the_player_of_three_minutes_is_small_and_has_sound() {
    let dir = tempfile::tempdir().unwrap();
    // Three minutes of MIDI: notes synthesized in the page.
    let mid = dir.path().join("piece.mid");
    write_midi(&mid, 360);
    let motion = dir.path().join("m.json");
    let page = dir.path().join("midi.html");
    let r = run(&[
        os("generate"),
        mid.as_os_str(),
        os("-o"),
        motion.as_os_str(),
        os("--preview"),
        page.as_os_str(),
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(
        html.contains("<script type=\"application/json\" id=\"notes\">[[0.000,0.500,67.00,"),
        "notes in the page"
    );
    let size = std::fs::metadata(&page).unwrap().len();
    assert!(size <= 3 << 20, "MIDI player of 3 min is {size} bytes");

    // Three minutes of WAV (7.6 MiB): linked beside the page, not embedded.
    let pages = dir.path().join("pages");
    std::fs::create_dir(&pages).unwrap();
    let wav = dir.path().join("take one.wav");
    write_wav(&wav, 180.0);
    let player = pages.join("p.html");
    let r = run(&[
        os("render"),
        motion.as_os_str(),
        os("--audio"),
        wav.as_os_str(),
        os("-o"),
        player.as_os_str(),
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    assert!(
        stderr(&r).contains("--embed-audio"),
        "the user is told: {}",
        stderr(&r)
    );
    let html = std::fs::read_to_string(&player).unwrap();
    assert!(html.contains("<audio id=\"audio\" preload=\"auto\" src=\"../take%20one.wav\">"));
    let size = std::fs::metadata(&player).unwrap().len();
    assert!(size <= 3 << 20, "audio player of 3 min is {size} bytes");
    // Asked for, the audio goes into the page.
    let r = run(&[
        os("render"),
        motion.as_os_str(),
        os("--audio"),
        wav.as_os_str(),
        os("-o"),
        player.as_os_str(),
        os("--embed-audio"),
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    assert!(std::fs::metadata(&player).unwrap().len() > 8 << 20);
}

#[test]
fn a_file_that_panics_a_codec_gives_one_line_and_exit_1() {
    let ogg = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../dsp-mel/tests/fixtures/audio/vorbis_codebook_panic.ogg");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.json");
    let r = run(&[os("analyze"), ogg.as_os_str(), os("-o"), out.as_os_str()]);
    let err = stderr(&r);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("vorbis_codebook_panic.ogg") && err.contains("damaged stream"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn inputs_longer_than_max_duration_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let mid = dir.path().join("piece.mid");
    write_midi(&mid, 16); // 8 s
    let wav = dir.path().join("rec.wav");
    write_wav(&wav, 2.0);
    let out = dir.path().join("m.json");
    let r = run(&[
        os("generate"),
        mid.as_os_str(),
        os("-o"),
        out.as_os_str(),
        os("--max-duration"),
        os("5"),
    ]);
    assert_eq!(r.status.code(), Some(1), "{}", stderr(&r));
    assert!(stderr(&r).contains("--max-duration") && stderr(&r).trim().lines().count() == 1);
    let r = run(&[
        os("analyze"),
        wav.as_os_str(),
        os("-o"),
        out.as_os_str(),
        os("--max-duration"),
        os("1"),
    ]);
    assert_eq!(r.status.code(), Some(1), "{}", stderr(&r));
    assert!(stderr(&r).contains("rec.wav: lasts 2 s"), "{}", stderr(&r));
    assert!(!out.exists());
    let r = run(&[
        os("analyze"),
        wav.as_os_str(),
        os("-o"),
        out.as_os_str(),
        os("--max-duration"),
        os("0"),
    ]);
    assert_eq!(r.status.code(), Some(2), "{}", stderr(&r));
    let r = run(&[
        os("generate"),
        mid.as_os_str(),
        os("-o"),
        out.as_os_str(),
        os("--max-duration"),
        os("9"),
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
}
