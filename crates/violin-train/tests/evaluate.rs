//! `evaluate` on a small corpus made by the corpus code: every SPEC §10 measure is present
//! and plausible, pooled per renderer and overall, and bad folders are typed errors.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use corpus::build::{build_corpus, CorpusConfig};
use corpus::etude::EtudeConfig;
use violin_skeleton::Pipeline;
use violin_train::evaluate::{evaluate_dir, SplitChoice};
use violin_train::TrainError;

#[test]
fn a_small_corpus_gets_every_measure() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = CorpusConfig {
        minutes: 1.0,
        seed: 3,
        etude: EtudeConfig {
            target_s: 12.0,
            ..EtudeConfig::default()
        },
        ..CorpusConfig::default()
    };
    let manifest = build_corpus(dir.path(), &cfg, &|_, _| {}).unwrap();
    let mut calls = 0;
    let report = evaluate_dir(
        &Pipeline::default(),
        dir.path(),
        SplitChoice::All,
        None,
        |_, _| calls += 1,
    )
    .unwrap();
    assert_eq!(report.layout, "corpus");
    assert_eq!(report.recordings.len(), manifest.items.len());
    assert_eq!(calls, manifest.items.len());
    assert_eq!(report.groups.len(), 1, "builtin renderer only");
    let s = &report.overall;
    println!("{}", report.table());
    for (name, v) in [
        ("bow-change F1", s.bow_change_f1),
        ("raw pitch accuracy", s.raw_pitch_accuracy),
        ("onset F1", s.onset_f1),
        ("beat F", s.beat_f),
        ("beat alignment", s.beat_alignment),
    ] {
        let v = v.unwrap_or_else(|| panic!("{name} missing"));
        assert!((0.0..=1.0).contains(&v), "{name} {v}");
    }
    assert!(s.bow_change_f1.unwrap() > 0.6, "{:?}", s.bow_change_f1);
    assert!(
        s.raw_pitch_accuracy.unwrap() > 0.85,
        "{:?}",
        s.raw_pitch_accuracy
    );
    assert!(s.onset_f1.unwrap() > 0.7, "{:?}", s.onset_f1);
    // The synthesis is the corpus's own, so poses are close but not identical.
    let l1 = s.skeleton_l1_px.unwrap();
    assert!(l1 > 0.0 && l1 < 40.0, "skeleton L1 {l1}");
    assert_eq!(s.bow_range_violations, Some(0.0));
    // 2-D bone lengths vary only through the camera's foreshortening of the rigid rig (its
    // 3-D rigidity is asserted in tests/pipeline.rs), so each recording's figure is of the
    // size of the corpus's own motion, drawn with the same rig and camera (how far the arms
    // swing follows the analysed notes, so it is not equal).
    for r in &report.recordings {
        let item = manifest
            .items
            .iter()
            .find(|i| i.dir.ends_with(&r.name) || r.name.ends_with(&i.dir))
            .unwrap_or_else(|| panic!("no manifest item for {}", r.name));
        let truth = violin_skeleton::Motion::read(
            dir.path().join(&item.dir).join("motion.json"),
            violin_skeleton::MotionFormat::Json,
        )
        .unwrap();
        let truth_cv = violin_skeleton::skeleton::metrics::bone_length_cv(truth.frames())
            .into_iter()
            .fold(0.0f32, f32::max);
        assert!(
            (0.5..1.5).contains(&(r.bone_length_cv / f64::from(truth_cv))),
            "{}: 2-D bone-length CV {} against the corpus motion's {truth_cv}",
            r.name,
            r.bone_length_cv
        );
    }

    let json = serde_json::to_string(&report).unwrap();
    let back: violin_train::evaluate::EvaluationReport = serde_json::from_str(&json).unwrap();
    assert_eq!(back.recordings.len(), report.recordings.len());

    // Only the test split, and a limit.
    let test = evaluate_dir(
        &Pipeline::default(),
        dir.path(),
        SplitChoice::Test,
        Some(1),
        |_, _| {},
    )
    .unwrap();
    assert_eq!(test.recordings.len(), 1);
}

#[test]
fn folders_without_labels_are_dataset_errors() {
    let dir = tempfile::tempdir().unwrap();
    let err = evaluate_dir(
        &Pipeline::default(),
        dir.path(),
        SplitChoice::All,
        None,
        |_, _| {},
    )
    .unwrap_err();
    assert!(matches!(err, TrainError::Dataset { .. }), "{err}");
    assert!(err.to_string().contains("neither a corpus"), "{err}");

    // A corpus item missing its labels names the file.
    std::fs::create_dir_all(dir.path().join("x")).unwrap();
    let cfg = CorpusConfig {
        minutes: 0.2,
        seed: 1,
        etude: EtudeConfig {
            target_s: 6.0,
            ..EtudeConfig::default()
        },
        ..CorpusConfig::default()
    };
    let corpus = dir.path().join("x");
    let manifest = build_corpus(&corpus, &cfg, &|_, _| {}).unwrap();
    let first = corpus.join(&manifest.items[0].dir);
    std::fs::remove_file(first.join("bowchanges.txt")).unwrap();
    let err = evaluate_dir(
        &Pipeline::default(),
        &corpus,
        SplitChoice::All,
        None,
        |_, _| {},
    )
    .unwrap_err();
    assert!(err.to_string().contains("bowchanges.txt"), "{err}");
}
