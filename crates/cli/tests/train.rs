//! `violin-skeleton train bowing|emotion` end to end on a tiny corpus, and its errors.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::process::Command;

use violin_skeleton::bowing_net::BowChangeDetector;
use violin_skeleton::emotion_net::ArousalEstimator;

fn cli() -> Command {
    Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
}

#[test]
fn trains_both_networks_on_a_tiny_corpus() {
    let dir = tempfile::tempdir().unwrap();
    let corpus = dir.path().join("corpus");
    let ok = cli()
        .args([
            "corpus",
            "--out",
            corpus.to_str().unwrap(),
            "--minutes",
            "1.5",
            "--seed",
            "3",
            "--quiet",
        ])
        .status()
        .unwrap();
    assert!(ok.success());
    for (net, epochs) in [("bowing", "1"), ("emotion", "2")] {
        let out = dir.path().join(format!("{net}.safetensors"));
        let report = dir.path().join(format!("{net}.json"));
        let o = cli()
            .args([
                "train",
                net,
                "--data",
                corpus.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ])
            .args([
                "--epochs",
                epochs,
                "--seed",
                "2",
                "--report",
                report.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{stderr}");
        assert!(
            stderr.contains("trained") && stderr.contains("test all"),
            "{stderr}"
        );
        assert!(out.with_extension("ckpt.safetensors").is_file());
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        assert!(json["all"].is_object(), "{json}");
        match net {
            "bowing" => assert!(BowChangeDetector::load(&out).is_ok()),
            _ => assert!(ArousalEstimator::load(&out).is_ok()),
        }
    }
}

#[test]
fn bad_arguments_fail_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let o = cli()
        .args([
            "train",
            "bowing",
            "--data",
            dir.path().to_str().unwrap(),
            "--out",
        ])
        .arg(dir.path().join("w.safetensors"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.starts_with("error: ") && stderr.contains("manifest.json"),
        "{stderr}"
    );
    let o = cli()
        .args([
            "train",
            "emotion",
            "--data",
            "x",
            "--out",
            "w.safetensors",
            "--epochs",
            "0",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let o = cli().args(["train", "--help"]).output().unwrap();
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("violin-skeleton train bowing --data corpus")
    );
}

fn tiny_corpus(dir: &std::path::Path, minutes: &str, seed: &str) {
    let ok = cli()
        .args(["corpus", "--out", dir.to_str().unwrap()])
        .args(["--minutes", minutes, "--seed", seed, "--quiet"])
        .status()
        .unwrap();
    assert!(ok.success());
}

#[test]
fn extra_training_corpora_join_the_training_split() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    tiny_corpus(&a, "1.5", "3");
    tiny_corpus(&b, "1", "4");
    let config = dir.path().join("steps.json");
    std::fs::write(&config, r#"{"max_steps_per_epoch": 3}"#).unwrap();
    let out = dir.path().join("w.safetensors");
    let o = cli()
        .args(["train", "bowing", "--data", a.to_str().unwrap()])
        .args(["--extra-train", b.to_str().unwrap()])
        .args([
            "--out",
            out.to_str().unwrap(),
            "--epochs",
            "1",
            "--seed",
            "2",
        ])
        .args(["--config", config.to_str().unwrap()])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    let count = |corpus: &std::path::Path| {
        let m: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(corpus.join("manifest.json")).unwrap())
                .unwrap();
        m["items"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|i| i["split"] == "train")
            .count()
    };
    let (na, nb) = (count(&a), count(&b));
    assert!(
        stderr.contains(&format!("{nb} training recordings added"))
            && stderr.contains(&format!("{} train,", na + nb)),
        "{stderr}"
    );
    assert!(BowChangeDetector::load(&out).is_ok());

    // Only the bowing network takes extra corpora; a folder that is not a corpus is named.
    let o = cli()
        .args(["train", "emotion", "--data", a.to_str().unwrap()])
        .args(["--extra-train", b.to_str().unwrap(), "--out"])
        .arg(dir.path().join("e.safetensors"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--extra-train applies to bowing"));
    let o = cli()
        .args(["train", "bowing", "--data", a.to_str().unwrap()])
        .args(["--extra-train", dir.path().to_str().unwrap(), "--out"])
        .arg(dir.path().join("x.safetensors"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.starts_with("error: ")
            && stderr.lines().count() == 1
            && stderr.contains("manifest.json"),
        "{stderr}"
    );
    assert!(!dir.path().join("x.safetensors").exists());
}
