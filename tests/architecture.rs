//! The house rules of ARCHITECTURE.md, checked on the code itself:
//!
//! * every workspace crate has a layer, and its normal and build dependencies (optional ones
//!   included) are crates of lower layers — within the tools layer, `cli` → `violin-train` →
//!   `corpus` (see the README's architecture section);
//! * no network crate depends on `corpus`, `pose-preproc`, `rustysynth` or another network;
//!   `pitch-track` and `beat-track` do not depend on each other; `net-core` not on `corpus`;
//! * the facade's default features compile no training code, corpus or SoundFont synthesizer;
//! * no FFT planner outside `dsp-mel`; no source file over 450 lines; no two source files
//!   that import each other.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

use common::imports::import_pairs;

/// Layer of every workspace crate, written ×10 so that an order inside a layer is a plain
/// comparison: in layer 0 `atomic-file` (0.0) comes before the crates that write files
/// (0.1); in layer 5 `corpus` (5.0) before `violin-train` (5.1) before `cli` (5.2).
const LAYERS: &[(&str, u32)] = &[
    ("atomic-file", 0),
    ("dsp-mel", 1),
    ("fingering", 1),
    ("skeleton", 1),
    ("performance", 10),
    ("net-core", 10),
    ("pitch-track", 20),
    ("beat-track", 20),
    ("pose-preproc", 20),
    ("bowing-net", 20),
    ("beat-net", 20),
    ("emotion-net", 20),
    ("gru-baseline", 20),
    ("motion-synth", 30),
    ("skeleton-render", 30),
    ("violin-skeleton", 40),
    ("corpus", 50),
    ("violin-train", 51),
    ("input-fuzz", 51),
    ("violin-skeleton-cli", 52),
    ("violin-skeleton-python", 52),
];

const NETWORKS: &[&str] = &["bowing-net", "beat-net", "emotion-net", "gru-baseline"];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn cargo(args: &[&str]) -> String {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .args(args)
        .current_dir(root())
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("utf-8")
}

/// Workspace crate → its declared normal and build dependencies (optional ones included).
fn declared_dependencies() -> BTreeMap<String, BTreeSet<String>> {
    let meta: serde_json::Value = serde_json::from_str(&cargo(&[
        "metadata",
        "--format-version",
        "1",
        "--no-deps",
        "--offline",
    ]))
    .expect("metadata is JSON");
    let mut out = BTreeMap::new();
    for pkg in meta["packages"].as_array().expect("packages") {
        let name = pkg["name"].as_str().expect("name").to_string();
        let deps = pkg["dependencies"]
            .as_array()
            .expect("dependencies")
            .iter()
            .filter(|d| d["kind"].is_null() || d["kind"] == "build")
            .map(|d| d["name"].as_str().expect("dep name").to_string())
            .collect();
        out.insert(name, deps);
    }
    out
}

fn layer(name: &str) -> Option<u32> {
    LAYERS.iter().find(|(n, _)| *n == name).map(|&(_, l)| l)
}

#[test]
fn every_crate_depends_only_on_lower_layers() {
    let deps = declared_dependencies();
    let mut wrong = Vec::new();
    for (name, ds) in &deps {
        let Some(own) = layer(name) else {
            wrong.push(format!("{name} has no layer in tests/architecture.rs"));
            continue;
        };
        for d in ds {
            if let Some(l) = layer(d) {
                if l >= own {
                    wrong.push(format!("{name} (layer {own}) → {d} (layer {l})"));
                }
            }
        }
    }
    for (name, _) in LAYERS {
        if !deps.contains_key(*name) {
            wrong.push(format!(
                "{name} is in the layer table but not in the workspace"
            ));
        }
    }
    assert!(wrong.is_empty(), "layer violations:\n{}", wrong.join("\n"));
}

#[test]
fn forbidden_dependencies_are_absent() {
    let deps = declared_dependencies();
    let mut wrong = Vec::new();
    let mut forbid = |from: &str, to: &str| {
        if deps.get(from).is_some_and(|d| d.contains(to)) {
            wrong.push(format!("{from} → {to}"));
        }
    };
    for net in NETWORKS {
        for to in ["corpus", "pose-preproc", "rustysynth", "violin-train"] {
            forbid(net, to);
        }
        for other in NETWORKS {
            forbid(net, other);
        }
    }
    forbid("pitch-track", "beat-track");
    forbid("beat-track", "pitch-track");
    forbid("net-core", "corpus");
    assert!(
        wrong.is_empty(),
        "forbidden dependencies:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn the_facade_by_default_compiles_no_training_corpus_or_soundfont() {
    let tree = cargo(&[
        "tree",
        "-p",
        "violin-skeleton",
        "-e",
        "normal",
        "--prefix",
        "none",
        "--offline",
    ]);
    let names: BTreeSet<&str> = tree.lines().filter_map(|l| l.split(' ').next()).collect();
    for banned in ["corpus", "rustysynth", "violin-train", "pose-preproc"] {
        assert!(
            !names.contains(banned),
            "the facade's default features compile {banned}"
        );
    }
    // No network's training loop either.
    let features = cargo(&[
        "tree",
        "-p",
        "violin-skeleton",
        "-e",
        "normal,features",
        "--prefix",
        "none",
        "--offline",
    ]);
    let train: Vec<&str> = features
        .lines()
        .filter(|l| l.contains("feature \"train\""))
        .collect();
    assert!(train.is_empty(), "default features turn on {train:?}");
}

/// Every `.rs` file we own, with its path relative to the root.
fn rust_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            let name = e.file_name();
            let name = name.to_string_lossy();
            if p.is_dir() {
                if !(name.starts_with('.') || name == "target" || name == "fuzz-target") {
                    walk(&p, out);
                }
            } else if name.ends_with(".rs") {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    for top in ["src", "crates", "tests", "benches", "examples", "fuzz"] {
        walk(&root().join(top), &mut out);
    }
    out.sort();
    out
}

#[test]
fn only_dsp_mel_plans_ffts() {
    let mut wrong = Vec::new();
    for file in rust_files() {
        let rel = file.strip_prefix(root()).expect("under root");
        if rel.starts_with("crates/dsp-mel") || rel == Path::new("tests/architecture.rs") {
            continue;
        }
        let text = std::fs::read_to_string(&file).expect("readable");
        if text.contains("FftPlanner") {
            wrong.push(rel.display().to_string());
        }
    }
    assert!(wrong.is_empty(), "FFT planners outside dsp-mel: {wrong:?}");
}

#[test]
fn no_source_file_is_over_450_lines() {
    let mut long = Vec::new();
    for file in rust_files() {
        let n = std::fs::read_to_string(&file)
            .expect("readable")
            .lines()
            .count();
        if n > 450 {
            long.push(format!(
                "{} ({n} lines)",
                file.strip_prefix(root()).expect("root").display()
            ));
        }
    }
    assert!(
        long.is_empty(),
        "files over 450 lines:\n{}",
        long.join("\n")
    );
}

#[test]
fn no_two_files_import_each_other() {
    let mut pairs = Vec::new();
    let mut src_dirs = vec![root().join("src")];
    for e in std::fs::read_dir(root().join("crates"))
        .expect("crates/")
        .flatten()
    {
        src_dirs.push(e.path().join("src"));
    }
    for dir in src_dirs {
        for (a, b) in import_pairs(&dir) {
            pairs.push(format!("{} ⇄ {}", a.display(), b.display()));
        }
    }
    assert!(
        pairs.is_empty(),
        "files that import each other:\n{}",
        pairs.join("\n")
    );
}
