//! `violin-skeleton corpus`: bad sizes and sources are usage errors with one line.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::process::Command;

fn cli() -> Command {
    Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
}

fn run(args: &[&str]) -> (i32, String) {
    let o = cli().args(args).output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).to_string(),
    )
}

#[test]
fn zero_or_negative_sizes_exit_2_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c");
    let out = out.to_str().unwrap();
    for args in [
        vec!["corpus", "--out", out, "--hours", "0"],
        vec!["corpus", "--out", out, "--hours=-1"],
        vec!["corpus", "--out", out, "--minutes", "0"],
        vec!["corpus", "--out", out, "--hours", "NaN"],
    ] {
        let (code, err) = run(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
    }
    assert!(!dir.path().join("c").exists());
}

#[test]
fn missing_sources_are_refused_with_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c");
    let out = out.to_str().unwrap();
    let (code, err) = run(&[
        "corpus",
        "--out",
        out,
        "--minutes",
        "1",
        "--renderer",
        "many",
        "--soundfont-dir",
        "/nonexistent/sf2",
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("/nonexistent/sf2"), "{err}");
    let (code, err) = run(&[
        "corpus",
        "--out",
        out,
        "--minutes",
        "1",
        "--renderer",
        "many",
        "--repertoire",
        "/nonexistent/scores",
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("/nonexistent/scores"), "{err}");
}

#[test]
fn a_recast_violin_needs_the_many_renderer_and_only_one_split() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c");
    let out = out.to_str().unwrap();
    for flag in ["--training-violin", "--validation-violin"] {
        let (code, err) = run(&["corpus", "--out", out, "--minutes", "1", flag, "/tmp"]);
        assert_eq!(code, 2, "{flag}: {err}");
        assert!(
            err.contains(flag) && err.contains("--renderer many"),
            "{err}"
        );
        assert_eq!(err.trim().lines().count(), 1, "{flag}: {err}");
    }
    let (code, err) = run(&[
        "corpus",
        "--out",
        out,
        "--renderer",
        "many",
        "--training-violin",
        "/tmp",
        "--validation-violin",
        "/tmp/v.pat",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cannot be used with"), "{err}");
    assert!(!dir.path().join("c").exists());
}
