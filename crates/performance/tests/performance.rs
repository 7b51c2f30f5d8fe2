//! Performance validation: bad inputs give typed errors; JSON round trips.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use performance::{ArousalCurve, Performance, PerformanceError, PerformanceFileError};

fn base() -> performance::PerformanceBuilder {
    Performance::builder(3.0)
        .note(0.0, 1.0, 67)
        .note(1.0, 2.0, 69)
}

#[test]
fn empty_zero_and_nan_durations_are_rejected() {
    assert_eq!(
        Performance::builder(3.0).build().unwrap_err(),
        PerformanceError::Empty
    );
    // 1e300 s: a damaged performance JSON found by input-fuzz (it overflowed an allocation).
    for d in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e300, 86_401.0] {
        let e = Performance::builder(d)
            .note(0.0, 0.5, 60)
            .build()
            .unwrap_err();
        assert!(
            matches!(e, PerformanceError::InvalidDuration { .. }),
            "{d}: {e}"
        );
    }
}

#[test]
fn bad_times_are_rejected_with_the_field_and_index() {
    let e = base().beats(vec![0.0, 1.0, 0.5]).build().unwrap_err();
    assert_eq!(
        e,
        PerformanceError::Unsorted {
            field: "beats_s",
            index: 2,
            value: 0.5
        }
    );
    let e = base().bow_changes(vec![1.0, f64::NAN]).build().unwrap_err();
    assert!(matches!(
        e,
        PerformanceError::NonFinite {
            field: "bow_changes_s",
            index: 1,
            ..
        }
    ));
    let e = base().downbeats(vec![0.0, 3.5]).build().unwrap_err();
    assert!(matches!(
        e,
        PerformanceError::OutOfRange {
            field: "downbeats_s",
            index: 1,
            ..
        }
    ));
    let e = base().bow_changes(vec![1.0, 1.0]).build().unwrap_err();
    assert!(matches!(e, PerformanceError::Unsorted { .. }));
    let e = base().note(2.5, 2.5, 60).build().unwrap_err();
    assert!(matches!(e, PerformanceError::EmptyNote { index: 2, .. }));
    let e = base().note(0.5, 0.9, 60).build().unwrap_err();
    assert!(matches!(
        e,
        PerformanceError::Unsorted {
            field: "notes.onset_s",
            index: 2,
            ..
        }
    ));
    let e = base().note(2.5, 3.2, 60).build().unwrap_err();
    assert!(matches!(
        e,
        PerformanceError::OutOfRange {
            field: "notes.offset_s",
            ..
        }
    ));
    let e = base().note(2.5, 2.9, 200).build().unwrap_err();
    assert_eq!(
        e,
        PerformanceError::InvalidMidi {
            index: 2,
            midi: 200
        }
    );
    assert!(e.to_string().contains("0..=127"));
}

#[test]
fn overlapping_notes_are_trimmed() {
    let p = Performance::builder(3.0)
        .note(0.0, 1.5, 67)
        .note(1.0, 2.0, 69)
        .build()
        .unwrap();
    assert_eq!(p.notes()[0].offset_s, 1.0);
}

#[test]
fn arousal_and_dynamics_are_checked() {
    let e = base()
        .arousal(ArousalCurve::deam(vec![0.0, 1.5]))
        .build()
        .unwrap_err();
    assert!(matches!(
        e,
        PerformanceError::ArousalOutOfRange { index: 1, .. }
    ));
    let e = base()
        .arousal(ArousalCurve::deam(vec![f32::NAN]))
        .build()
        .unwrap_err();
    assert!(matches!(
        e,
        PerformanceError::NonFinite {
            field: "arousal.values",
            ..
        }
    ));
    let e = base()
        .arousal(ArousalCurve {
            rate_hz: 0.0,
            values: vec![0.0],
        })
        .build()
        .unwrap_err();
    assert!(matches!(e, PerformanceError::InvalidArousalRate { .. }));
    assert!(base()
        .arousal(ArousalCurve::clamped(2.0, vec![3.0, -2.0]))
        .build()
        .is_ok());
    let e = base().dynamics(vec![0.5]).build().unwrap_err();
    assert_eq!(
        e,
        PerformanceError::DynamicsLength {
            expected: 2,
            got: 1
        }
    );
    let e = base().dynamics(vec![0.5, 1.5]).build().unwrap_err();
    assert!(matches!(
        e,
        PerformanceError::DynamicsOutOfRange { index: 1, .. }
    ));
}

#[test]
fn json_round_trips_and_reads_analysis_files() {
    let p = base()
        .bow_changes(vec![1.0])
        .beats(vec![0.0, 0.5])
        .arousal(ArousalCurve::deam(vec![0.1, 0.2]))
        .build()
        .unwrap()
        .with_fingering(&fingering::OptimalPlanner::default())
        .unwrap();
    let text = serde_json::to_string(&p).unwrap();
    assert_eq!(serde_json::from_str::<Performance>(&text).unwrap(), p);
    // An analysis.json (extra fields, flattened fingering) reads as a performance.
    let analysis = r#"{"duration_s": 2.0, "sample_rate": 22050, "tempo_bpm": 100,
        "f0": {"hop_s": 0.01, "hz": [], "voiced_prob": []},
        "notes": [{"onset_s": 0.0, "offset_s": 1.0, "midi": 69, "string": 3, "position": 1, "finger": 0}],
        "bow_changes_s": [1.0], "beats_s": [], "downbeats_s": [], "arousal": {"rate_hz": 2, "values": [0.0]}}"#;
    let a: Performance = serde_json::from_str(analysis).unwrap();
    assert_eq!(
        a.notes()[0].fingering.unwrap().string,
        fingering::ViolinString::A
    );
    // Validation runs on deserialisation too.
    let bad = r#"{"duration_s": 0, "notes": [{"onset_s": 0, "offset_s": 1, "midi": 60}]}"#;
    assert!(serde_json::from_str::<Performance>(bad)
        .unwrap_err()
        .to_string()
        .contains("duration"));
}

#[test]
fn read_json_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("perf.json");
    std::fs::write(&path, "{\"duration_s\": 1, \"notes\": [").unwrap();
    let e = Performance::read_json(&path).unwrap_err();
    assert!(matches!(e, PerformanceFileError::Parse { .. }));
    assert!(e.to_string().contains("perf.json"));
    let e = Performance::read_json(dir.path().join("missing.json")).unwrap_err();
    assert!(matches!(e, PerformanceFileError::Io { .. }));
}

#[test]
fn double_stops_are_a_second_voice_checked_like_notes() {
    use performance::Note;
    // G4 under E5 for the second note, and a three-note chord's two lower notes.
    let voice = vec![
        Note::new(1.0, 2.0, 55),
        Note::new(1.0, 2.0, 62),
        Note::new(1.5, 1.9, 64),
    ];
    let p = base().double_stops(voice.clone()).build().unwrap();
    assert_eq!(p.double_stops(), voice.as_slice());
    assert_eq!(p.notes().len(), 2); // the line is untouched
    let text = serde_json::to_string(&p).unwrap();
    assert!(text.contains("double_stops"));
    assert_eq!(serde_json::from_str::<Performance>(&text).unwrap(), p);
    // A single line writes no double_stops field.
    let plain = serde_json::to_string(&base().build().unwrap()).unwrap();
    assert!(!plain.contains("double_stops"));

    let err = |notes: Vec<Note>| base().double_stops(notes).build().unwrap_err();
    let e = err(vec![Note::new(1.0, 1.0, 60)]);
    assert!(matches!(
        e,
        PerformanceError::InvalidDoubleStop { index: 0, .. }
    ));
    assert!(e.to_string().contains("not after its onset"), "{e}");
    let e = err(vec![Note::new(1.5, 2.0, 60), Note::new(1.0, 2.0, 62)]);
    assert!(e.to_string().contains("double_stops[1]"), "{e}");
    assert!(e.to_string().contains("sort by onset"), "{e}");
    let e = err(vec![Note::new(1.0, 9.0, 60)]);
    assert!(matches!(
        e,
        PerformanceError::OutOfRange {
            field: "double_stops.offset_s",
            ..
        }
    ));
    let e = err(vec![Note::new(f64::NAN, 1.0, 60)]);
    assert!(matches!(
        e,
        PerformanceError::NonFinite {
            field: "double_stops.onset_s",
            ..
        }
    ));
    assert!(err(vec![Note::new(1.0, 2.0, 200)])
        .to_string()
        .contains("MIDI pitch 200"));
}
