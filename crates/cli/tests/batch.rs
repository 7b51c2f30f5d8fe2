//! Batch mode end to end: `generate DIR -o OUTDIR` and `analyze DIR -o OUTDIR` with good,
//! broken, unreadable and non-music files; outputs equal the single-file commands'; the
//! summary names every failure; `--skip-existing` resumes.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::{Command, Output};

use corpus::item::clean_etude;
use serde_json::Value;

mod common;
use common::write_samples_wav as write_wav;

fn cli() -> Command {
    Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
}

fn run(args: &[&str], input: &Path, out: &Path) -> Output {
    cli()
        .args(args)
        .arg(input)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("batch_summary.json")).unwrap()).unwrap()
}

/// A folder with two études (one in a subfolder), a `.wav` that is text, a link to nothing
/// and a text file.
fn music_folder(root: &Path) -> std::path::PathBuf {
    let inp = root.join("takes");
    std::fs::create_dir_all(inp.join("day2")).unwrap();
    for (seed, name) in [(3u64, "a.wav"), (4, "day2/b.wav")] {
        let item = clean_etude(seed, 6.0, (100.0, 100.0)).unwrap();
        write_wav(&inp.join(name), &item.audio, 22_050);
    }
    std::fs::write(inp.join("broken.wav"), b"this is not a wave file").unwrap();
    std::fs::write(inp.join("readme.txt"), b"liner notes").unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(root.join("nowhere.wav"), inp.join("gone.wav")).unwrap();
    inp
}

#[test]
fn generate_on_a_folder_writes_the_rest_and_names_the_failures() {
    let dir = tempfile::tempdir().unwrap();
    let inp = music_folder(dir.path());
    let out = dir.path().join("motion");
    let o = run(&["generate", "--jobs", "2"], &inp, &out);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("broken.wav"), "{err}");
    assert!(err.contains("batch_summary.json"), "{err}");

    // The good files are written, mirrored, and equal to the single-file command's output.
    for rel in ["a", "day2/b"] {
        let batch = std::fs::read(out.join(format!("{rel}.json"))).unwrap();
        let single = dir.path().join("single.json");
        let s = run(&["generate"], &inp.join(format!("{rel}.wav")), &single);
        assert!(s.status.success(), "{}", stderr(&s));
        assert_eq!(batch, std::fs::read(&single).unwrap(), "{rel}");
    }
    let s = summary(&out);
    assert_eq!(s["files"], 4);
    assert_eq!(s["written"], 2);
    assert_eq!(s["jobs"], 2);
    let failed: Vec<String> = s["failed"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["file"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(failed.len(), if cfg!(unix) { 2 } else { 1 }, "{s}");
    assert!(failed[0].ends_with("broken.wav"), "{failed:?}");
    for f in s["failed"].as_array().unwrap() {
        assert!(!f["error"].as_str().unwrap().is_empty());
    }
    assert_eq!(s["not_music"], serde_json::json!(["readme.txt"]));

    // Resume: nothing is redone, the failures are tried again.
    let before = std::fs::metadata(out.join("a.json"))
        .unwrap()
        .modified()
        .unwrap();
    let o = run(&["generate", "--skip-existing"], &inp, &out);
    assert_eq!(o.status.code(), Some(1));
    let s = summary(&out);
    assert_eq!(s["skipped_existing"], 2);
    assert_eq!(s["written"], 0);
    let after = std::fs::metadata(out.join("a.json"))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(before, after);

    // Without the broken files the batch succeeds.
    std::fs::remove_file(inp.join("broken.wav")).unwrap();
    #[cfg(unix)]
    std::fs::remove_file(inp.join("gone.wav")).unwrap();
    let o = run(&["generate", "--format", "csv"], &inp, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("day2/b.csv").is_file());
}

#[test]
fn analyze_on_a_folder_equals_analyze_per_file() {
    let dir = tempfile::tempdir().unwrap();
    let inp = music_folder(dir.path());
    let out = dir.path().join("analyses");
    let o = run(&["analyze", "--jobs", "2", "--f0-fps", "30"], &inp, &out);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let single = dir.path().join("one.json");
    let s = run(
        &["analyze", "--f0-fps", "30"],
        &inp.join("day2/b.wav"),
        &single,
    );
    assert!(s.status.success(), "{}", stderr(&s));
    assert_eq!(
        std::fs::read(out.join("day2/b.json")).unwrap(),
        std::fs::read(&single).unwrap()
    );
    assert!(out.join("a.json").is_file());
    assert!(!out.join("broken.json").exists());
}

#[test]
fn single_file_flags_are_refused_with_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    let inp = dir.path().join("in");
    std::fs::create_dir(&inp).unwrap();
    let out = dir.path().join("out");
    for extra in [
        vec!["generate", "--preview", "p.html"],
        vec!["generate", "--analysis-out", "a.json"],
    ] {
        let o = run(&extra, &inp, &out);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
        assert_eq!(stderr(&o).trim().lines().count(), 1, "{}", stderr(&o));
        assert!(!out.exists());
    }
    for bad_out in [dir.path().join("motion.json"), inp.clone()] {
        let o = run(&["generate"], &inp, &bad_out);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert_eq!(stderr(&o).trim().lines().count(), 1, "{}", stderr(&o));
    }
    let o = run(&["generate", "--jobs", "0"], &inp, &out);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = run(&["analyze"], &inp, Path::new("-"));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    // An empty folder is a successful batch of nothing.
    let o = run(&["analyze"], &inp, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(summary(&out)["files"], 0);
}
