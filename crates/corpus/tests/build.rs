//! Building a small corpus: the layout, the manifest, and bit-for-bit determinism.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use corpus::build::{build_corpus, CorpusConfig, RendererChoice};
use corpus::etude::EtudeConfig;
use corpus::manifest::{Manifest, Split};

fn small(renderer: RendererChoice) -> CorpusConfig {
    CorpusConfig {
        minutes: 0.5,
        seed: 9,
        renderer,
        augment: true,
        etude: EtudeConfig {
            target_s: 10.0,
            ..EtudeConfig::default()
        },
        repertoire: None,
        validation_violin: None,
        training_violin: None,
    }
}

fn files(root: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(root).unwrap().to_string_lossy().to_string();
                out.push((rel, std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

#[test]
fn layout_manifest_and_determinism() {
    let a = tempfile::tempdir().unwrap();
    let b = tempfile::tempdir().unwrap();
    let m = build_corpus(a.path(), &small(RendererChoice::Builtin), &|_, _| {}).unwrap();
    build_corpus(b.path(), &small(RendererChoice::Builtin), &|_, _| {}).unwrap();
    assert_eq!(m.items.len(), 3);
    let splits: Vec<Split> = m.items.iter().map(|i| i.split).collect();
    assert!(
        splits.contains(&Split::Train)
            && splits.contains(&Split::Val)
            && splits.contains(&Split::Test)
    );
    for item in &m.items {
        let dir = a.path().join(&item.dir);
        for f in [
            "audio.wav",
            "performance.json",
            "notes.tsv",
            "bowchanges.txt",
            "beats.txt",
            "downbeats.txt",
            "arousal.csv",
            "motion.json",
        ] {
            assert!(dir.join(f).is_file(), "{} missing {f}", item.dir);
        }
        let notes = std::fs::read_to_string(dir.join("notes.tsv")).unwrap();
        assert_eq!(notes.lines().count(), item.notes + 1);
        let audio = dsp_mel_free_duration(&dir.join("audio.wav"));
        assert!((audio - item.duration_s).abs() < 0.01);
    }
    let manifest: Manifest =
        serde_json::from_str(&std::fs::read_to_string(a.path().join("manifest.json")).unwrap())
            .unwrap();
    assert_eq!(manifest, m);
    assert!(m.stats.bow_change_share_of_onsets > 0.3 && m.stats.bow_change_share_of_onsets <= 1.0);
    // Same seed, same bytes.
    assert_eq!(files(a.path()), files(b.path()));
}

fn dsp_mel_free_duration(path: &Path) -> f64 {
    let r = hound::WavReader::open(path).unwrap();
    f64::from(r.duration()) / f64::from(r.spec().sample_rate)
}

#[test]
fn soundfont_mix_uses_both_renderers() {
    let dir = tempfile::tempdir().unwrap();
    let font = dir.path().join("tiny.sf2");
    std::fs::write(&font, corpus::render::tiny_violin_sf2()).unwrap();
    let out = dir.path().join("corpus");
    let m = build_corpus(&out, &small(RendererChoice::Mix(font)), &|_, _| {}).unwrap();
    let kinds: std::collections::HashSet<_> = m.items.iter().map(|i| i.renderer).collect();
    assert_eq!(kinds.len(), 2);
    // Over a large corpus, the test and validation splits get both renderers too.
    for split in [corpus::manifest::Split::Test, corpus::manifest::Split::Val] {
        let assigned = corpus::manifest::Split::assign(100);
        let kinds: std::collections::HashSet<bool> = (0..100)
            .filter(|&i| assigned[i] == split)
            .map(corpus::build::mix_uses_soundfont)
            .collect();
        assert_eq!(kinds.len(), 2, "{split:?}");
    }
}

#[test]
fn bad_settings_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let mut cfg = small(RendererChoice::Builtin);
    cfg.minutes = f64::NAN;
    assert!(build_corpus(dir.path(), &cfg, &|_, _| {}).is_err());
    let cfg = small(RendererChoice::Soundfont("/no/such.sf2".into()));
    let err = build_corpus(dir.path(), &cfg, &|_, _| {}).unwrap_err();
    assert!(err.to_string().contains("/no/such.sf2"));
}
