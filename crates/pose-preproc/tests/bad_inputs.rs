//! Bad OpenPose directories: each a typed error naming the file or directory.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use pose_preproc::{preprocess_dir, PosePreprocError, PreprocConfig};
use serde_json::json;

fn person(keypoints: usize, conf: f32) -> serde_json::Value {
    let kp: Vec<f32> = (0..keypoints)
        .flat_map(|k| [500.0 + 10.0 * k as f32, 300.0 + 7.0 * (k % 5) as f32, conf])
        .collect();
    json!({ "pose_keypoints_2d": kp })
}

fn write(dir: &Path, frame: usize, people: Vec<serde_json::Value>) {
    let doc = json!({ "version": 1.3, "people": people });
    std::fs::write(
        dir.join(format!("v_{frame:012}_keypoints.json")),
        doc.to_string(),
    )
    .unwrap();
}

fn run(dir: &Path) -> PosePreprocError {
    preprocess_dir(dir, &PreprocConfig::default()).unwrap_err()
}

fn mentions(e: &PosePreprocError, what: &str) {
    assert!(
        e.to_string().contains(what),
        "`{e}` does not mention {what}"
    );
}

#[test]
fn missing_empty_and_jsonless_directories() {
    let root = tempfile::tempdir().unwrap();
    let missing = root.path().join("nope");
    let e = run(&missing);
    assert!(matches!(e, PosePreprocError::NotFound { .. }), "{e}");
    mentions(&e, "nope");

    let file = root.path().join("file.json");
    std::fs::write(&file, "{}").unwrap();
    assert!(matches!(run(&file), PosePreprocError::NotADirectory { .. }));

    let empty = root.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let e = run(&empty);
    assert!(matches!(e, PosePreprocError::EmptyDirectory { .. }), "{e}");
    mentions(&e, "empty");

    let other = root.path().join("other");
    std::fs::create_dir(&other).unwrap();
    std::fs::write(other.join("video.mp4"), b"x").unwrap();
    std::fs::write(other.join("notes.txt"), b"x").unwrap();
    let e = run(&other);
    assert!(
        matches!(e, PosePreprocError::NoJsonFiles { entries: 2, .. }),
        "{e}"
    );
    mentions(&e, "other");
}

#[test]
fn malformed_truncated_and_empty_json_files_are_named() {
    let dir = tempfile::tempdir().unwrap();
    for t in 0..20 {
        write(dir.path(), t, vec![person(25, 0.9)]);
    }
    let bad = dir.path().join("v_000000000007_keypoints.json");
    let text = std::fs::read_to_string(&bad).unwrap();
    std::fs::write(&bad, &text[..text.len() / 2]).unwrap();
    let e = run(dir.path());
    assert!(matches!(e, PosePreprocError::MalformedJson { .. }), "{e}");
    mentions(&e, "v_000000000007_keypoints.json");
    mentions(&e, "line 1 column");

    std::fs::write(&bad, b"").unwrap();
    let e = run(dir.path());
    assert!(matches!(e, PosePreprocError::MalformedJson { .. }), "{e}");
    mentions(&e, "000000000007");

    std::fs::write(
        &bad,
        r#"{"people": [{"pose_keypoints_2d": [1.0, "x", 0.5]}]}"#,
    )
    .unwrap();
    assert!(matches!(
        run(dir.path()),
        PosePreprocError::MalformedJson { .. }
    ));
}

#[test]
fn wrong_keypoint_count_names_file_and_count() {
    let dir = tempfile::tempdir().unwrap();
    for t in 0..5 {
        write(dir.path(), t, vec![person(25, 0.9)]);
    }
    write(dir.path(), 3, vec![person(25, 0.9), person(19, 0.9)]);
    let e = run(dir.path());
    assert!(
        matches!(
            e,
            PosePreprocError::WrongKeypointCount {
                person: 1,
                values: 57,
                keypoints: 19,
                ..
            }
        ),
        "{e}"
    );
    mentions(&e, "v_000000000003_keypoints.json");
    mentions(&e, "57");
    // Not a multiple of 3.
    let doc = json!({"people": [{"pose_keypoints_2d": vec![1.0; 76]}]});
    std::fs::write(
        dir.path().join("v_000000000003_keypoints.json"),
        doc.to_string(),
    )
    .unwrap();
    assert!(matches!(
        run(dir.path()),
        PosePreprocError::WrongKeypointCount { values: 76, .. }
    ));
}

#[test]
fn no_person_in_any_frame() {
    let dir = tempfile::tempdir().unwrap();
    for t in 0..10 {
        write(dir.path(), t, vec![]);
    }
    let e = run(dir.path());
    assert!(
        matches!(e, PosePreprocError::NoPerson { frames: 10, .. }),
        "{e}"
    );
    // People too unsure of themselves to be anyone are no person either.
    for t in 0..10 {
        write(dir.path(), t, vec![person(18, 0.01)]);
    }
    let e = run(dir.path());
    assert!(matches!(e, PosePreprocError::NoPerson { .. }), "{e}");
    mentions(&e, &dir.path().display().to_string());
}

#[test]
fn mixed_layouts_name_both_files() {
    let dir = tempfile::tempdir().unwrap();
    for t in 0..6 {
        write(
            dir.path(),
            t,
            vec![person(if t < 4 { 18 } else { 25 }, 0.9)],
        );
    }
    let e = run(dir.path());
    assert!(matches!(e, PosePreprocError::MixedLayouts { .. }), "{e}");
    mentions(&e, "v_000000000000_keypoints.json");
    mentions(&e, "v_000000000004_keypoints.json");
    // Two layouts inside one file too.
    write(dir.path(), 4, vec![person(18, 0.9), person(25, 0.9)]);
    write(dir.path(), 5, vec![person(18, 0.9)]);
    assert!(matches!(
        run(dir.path()),
        PosePreprocError::MixedLayouts { .. }
    ));
}

#[test]
fn unordered_names_duplicates_and_never_detected_joints() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("take_keypoints.json"), "{}").unwrap();
    let e = run(dir.path());
    assert!(matches!(e, PosePreprocError::NoFrameNumber { .. }), "{e}");
    std::fs::remove_file(dir.path().join("take_keypoints.json")).unwrap();

    write(dir.path(), 0, vec![person(25, 0.9)]);
    let doc = json!({"people": [person(25, 0.9)]});
    std::fs::write(
        dir.path().join("other_000000000000_keypoints.json"),
        doc.to_string(),
    )
    .unwrap();
    let e = run(dir.path());
    assert!(
        matches!(e, PosePreprocError::DuplicateFrame { frame: 0, .. }),
        "{e}"
    );
    std::fs::remove_file(dir.path().join("other_000000000000_keypoints.json")).unwrap();

    // The left hip (BODY_25 index 12) is never confident.
    let mut p = person(25, 0.9);
    p["pose_keypoints_2d"][3 * 12 + 2] = json!(0.0);
    for t in 0..20 {
        write(dir.path(), t, vec![p.clone()]);
    }
    let e = run(dir.path());
    assert!(
        matches!(
            e,
            PosePreprocError::JointNeverDetected { joint: "l_hip", .. }
        ),
        "{e}"
    );
}

#[test]
fn invalid_configuration_is_rejected() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), 0, vec![person(25, 0.9)]);
    for cfg in [
        PreprocConfig {
            median_window: 4,
            ..Default::default()
        },
        PreprocConfig {
            fps: 0.0,
            ..Default::default()
        },
        PreprocConfig {
            confidence_threshold: 2.0,
            ..Default::default()
        },
    ] {
        let e = preprocess_dir(dir.path(), &cfg).unwrap_err();
        assert!(matches!(e, PosePreprocError::InvalidConfig(_)), "{e}");
    }
}

#[test]
fn nan_infinity_and_negative_coordinates_are_dropped_and_reported() {
    let dir = tempfile::tempdir().unwrap();
    for t in 0..40 {
        write(dir.path(), t, vec![person(25, 0.9)]);
    }
    // Python's json module writes NaN and Infinity as bare tokens.
    let nan = dir.path().join("v_000000000005_keypoints.json");
    let text = std::fs::read_to_string(&nan).unwrap();
    let text = text
        .replacen("500.0", "NaN", 1)
        .replacen("0.9", "Infinity", 1);
    std::fs::write(&nan, text).unwrap();
    let mut p = person(25, 0.9);
    p["pose_keypoints_2d"][3 * 4] = json!(-12.0);
    write(dir.path(), 9, vec![p]);
    let track = preprocess_dir(dir.path(), &PreprocConfig::default()).unwrap();
    assert!(track.motion.frames().iter().all(|v| v.is_finite()));
    let note = track
        .quality
        .notes
        .iter()
        .find(|n| n.contains("negative or non-numeric"))
        .expect("a note");
    assert!(note.contains("v_000000000005_keypoints.json"), "{note}");
    assert!(
        note.starts_with("2 keypoints") || note.starts_with("3 keypoints"),
        "{note}"
    );
}

#[test]
fn files_that_are_not_frames_are_skipped_and_named() {
    let dir = tempfile::tempdir().unwrap();
    for t in 0..20 {
        write(dir.path(), t, vec![person(25, 0.9)]);
    }
    std::fs::write(dir.path().join("video.mp4"), b"\x00\x01").unwrap();
    std::fs::write(dir.path().join("settings.json"), b"not json at all").unwrap();
    let track = preprocess_dir(dir.path(), &PreprocConfig::default()).unwrap();
    let note = track
        .quality
        .notes
        .iter()
        .find(|n| n.starts_with("skipped 2 entries"))
        .expect("a note");
    assert!(
        note.contains("video.mp4") && note.contains("settings.json"),
        "{note}"
    );
    // A .json frame file that is not JSON is an error naming it.
    std::fs::write(dir.path().join("v_000000000003_keypoints.json"), b"\x89PNG").unwrap();
    let e = run(dir.path());
    assert!(matches!(e, PosePreprocError::MalformedJson { .. }), "{e}");
    mentions(&e, "v_000000000003_keypoints.json");
    assert_eq!(e.to_string().lines().count(), 1);
}
