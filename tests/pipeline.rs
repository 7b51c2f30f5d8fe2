//! The facade end to end on the demo clip (the Minuet in G rendered by the corpus code):
//! analysis close to what was played, and a plausible motion.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use corpus::melodies::minuet_in_g;
use corpus::render::{BowedStringSynth, RenderSettings, Renderer};
use corpus::timing::play;
use pose_preproc::metrics::match_events_s;
use violin_skeleton::fingering::OptimalPlanner;
use violin_skeleton::motion_synth::{metrics, synthesize_detailed};
use violin_skeleton::{Audio, Pipeline};

#[test]
fn demo_clip_gives_a_plausible_violinist() {
    let mut timeline = play(&minuet_in_g(), 1);
    timeline.assign_fingering(&OptimalPlanner::default());
    let settings = RenderSettings {
        sample_rate_hz: 22_050,
        tuning_cents: 0.0,
        seed: 1,
    };
    let samples = BowedStringSynth::default()
        .render(&timeline, &settings)
        .unwrap();
    let audio = Audio::new(samples, 22_050).unwrap();
    let pipeline = Pipeline::default();
    let analysis = pipeline.analyze(&audio).unwrap();

    let onsets: Vec<f64> = timeline.notes.iter().map(|n| n.note.onset_s).collect();
    let found: Vec<f64> = analysis.notes.iter().map(|n| n.onset_s).collect();
    let notes = match_events_s(&found, &onsets, 0.05);
    let changes = match_events_s(&analysis.bow_changes_s, &timeline.bow_changes_s(), 0.1);
    println!(
        "note onset F1 {:.2}, bow-change F1 {:.2}",
        notes.f1, changes.f1
    );
    assert!(notes.f1 > 0.8, "note onsets F1 {}", notes.f1);
    assert!(changes.f1 > 0.7, "bow changes F1 {}", changes.f1);
    // The minuet is 3/4 at 120 bpm: the beat is the quarter note, not the bar (a beat-net
    // trained where every beat was louder read it at 40 bpm; crates/beat-net/README.md).
    assert!(
        (analysis.tempo_bpm / 120.0 - 1.0).abs() <= 0.08,
        "tempo {} bpm, the minuet is played at 120",
        analysis.tempo_bpm
    );
    // Every bow change well inside a note has split it (a new bow is a new note).
    let guard = violin_skeleton::BOW_CHANGE_SPLIT_MIN_PART_S;
    for t in &analysis.bow_changes_s {
        assert!(
            !analysis
                .notes
                .iter()
                .any(|n| *t >= n.onset_s + guard && *t <= n.offset_s - guard),
            "bow change at {t} s lies inside a note"
        );
    }
    assert!(analysis
        .arousal
        .values
        .iter()
        .all(|a| (-1.0..=1.0).contains(a)));

    let perf = pipeline.performance(&analysis).unwrap();
    let out = synthesize_detailed(&perf, pipeline.synth_config()).unwrap();
    assert_eq!(metrics::bow_range_violations(out.bow.positions()), 0.0);
    assert!(out.motion.max_bone_length_cv() < 0.005);
    assert!(out.motion.frames().iter().all(|v| v.is_finite()));
    assert!((out.motion.duration_s() - audio.duration_s()).abs() < 0.1);
}
