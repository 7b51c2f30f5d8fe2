//! Reading details: frame order, numbering holes, 3-D keypoints, short clips, and the label
//! pipeline's filters against scipy's fixtures.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{generate, write_openpose_dir, SynthConfig};
use pose_preproc::labels::{lowpass, smoothed_velocity};
use pose_preproc::{preprocess_dir, read_openpose_dir, LabelConfig, PreprocConfig};
use serde_json::json;
use skeleton::{Joint, PoseLayout};

/// A COCO-18 person whose nose x is `x` (all joints confident).
fn person_at(x: f32) -> serde_json::Value {
    let kp: Vec<f32> = (0..18)
        .flat_map(|k| [x + 10.0 * k as f32, 200.0 + 20.0 * k as f32, 0.9])
        .collect();
    json!({ "pose_keypoints_2d": kp })
}

#[test]
fn frames_are_ordered_by_the_number_in_the_name() {
    let dir = tempfile::tempdir().unwrap();
    // Unpadded numbers: lexicographic order would put 10 before 2.
    for t in [0usize, 1, 2, 10, 11, 3, 4, 5, 6, 7, 8, 9] {
        let doc = json!({ "people": [person_at(100.0 + t as f32)] });
        std::fs::write(
            dir.path().join(format!("clip_{t}_keypoints.json")),
            doc.to_string(),
        )
        .unwrap();
    }
    // Stray JSON that is not a keypoints file is ignored when keypoints files exist.
    std::fs::write(dir.path().join("settings.json"), "{\"a\": 1}").unwrap();
    let raw = read_openpose_dir(dir.path()).unwrap();
    assert_eq!(
        (raw.layout, raw.frames.len(), raw.source_files),
        (PoseLayout::Coco18, 12, 12)
    );
    for (t, people) in raw.frames.iter().enumerate() {
        assert_eq!(people[0].joints[0][0], 100.0 + t as f32);
    }
}

#[test]
fn numbering_holes_become_frames_without_performer() {
    let dir = tempfile::tempdir().unwrap();
    for t in (5..40usize).filter(|t| ![12, 13, 30].contains(t)) {
        let doc = json!({ "people": [person_at(300.0 + t as f32)] });
        std::fs::write(
            dir.path().join(format!("v_{t:012}_keypoints.json")),
            doc.to_string(),
        )
        .unwrap();
    }
    let cfg = PreprocConfig {
        center: false,
        median_window: 1,
        ..Default::default()
    };
    let track = preprocess_dir(dir.path(), &cfg).unwrap();
    let q = &track.quality;
    assert_eq!(
        (q.frames, q.source_files, q.missing_frame_files),
        (35, 32, 3)
    );
    assert_eq!(q.frames_without_performer, 3);
    assert_eq!(q.filled_joint_frames, 30); // 3 frames × 10 joints, interpolated
    assert!(
        q.notes
            .iter()
            .any(|n| n.contains("3 frame numbers had no file")),
        "{:?}",
        q.notes
    );
    // Frame 12 − 5 = 7 is interpolated between the neighbours: nose x = 300 + 12.
    assert!((track.motion.joint(Joint::Nose)[[7, 0]] - 312.0).abs() < 1e-3);
}

#[test]
fn z_is_dropped_from_3d_keypoints() {
    let dir = tempfile::tempdir().unwrap();
    for t in 0..20usize {
        let kp: Vec<f32> = (0..25)
            .flat_map(|k| [400.0 + k as f32 * 9.0, 300.0 + t as f32, 55.5, 0.8])
            .collect();
        let doc = json!({ "people": [{ "pose_keypoints_2d": [], "pose_keypoints_3d": kp }] });
        std::fs::write(
            dir.path().join(format!("v_{t:012}_keypoints.json")),
            doc.to_string(),
        )
        .unwrap();
    }
    let raw = read_openpose_dir(dir.path()).unwrap();
    assert_eq!(raw.layout, PoseLayout::Body25);
    let d = raw.frames[3][0];
    assert_eq!(
        d.joints[Joint::RHip.index()],
        [400.0 + 9.0 * 9.0, 303.0, 0.8]
    );
}

#[test]
fn short_clip_gets_no_labels_and_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let clip = generate(&SynthConfig::standard(15, PoseLayout::Body25, 1));
    write_openpose_dir(dir.path(), &clip, "short");
    let track = preprocess_dir(dir.path(), &PreprocConfig::default()).unwrap();
    assert_eq!(track.motion.len(), 15);
    assert!(track.bow_change_frames.is_empty());
    assert!(
        track.quality.notes.iter().any(|n| n.contains("too short")),
        "{:?}",
        track.quality.notes
    );
    // A single frame is a valid (if useless) clip.
    let one = tempfile::tempdir().unwrap();
    let doc = json!({ "people": [person_at(10.0)] });
    std::fs::write(
        one.path().join("x_000000000000_keypoints.json"),
        doc.to_string(),
    )
    .unwrap();
    assert_eq!(
        preprocess_dir(one.path(), &PreprocConfig::default())
            .unwrap()
            .motion
            .len(),
        1
    );
}

#[test]
fn a_one_frame_giant_at_the_start_is_not_the_performer() {
    let dir = tempfile::tempdir().unwrap();
    for t in 0..40usize {
        let mut people = vec![person_at(100.0)];
        if t == 0 {
            // Much larger and more confident, but present for one frame only.
            let kp: Vec<f32> = (0..18)
                .flat_map(|k| [900.0 + 40.0 * k as f32, 50.0 + 60.0 * k as f32, 1.0])
                .collect();
            people.insert(0, json!({ "pose_keypoints_2d": kp }));
        }
        let doc = json!({ "people": people });
        std::fs::write(
            dir.path().join(format!("v_{t:012}_keypoints.json")),
            doc.to_string(),
        )
        .unwrap();
    }
    let cfg = PreprocConfig {
        center: false,
        ..Default::default()
    };
    let track = preprocess_dir(dir.path(), &cfg).unwrap();
    assert_eq!(track.motion.joint(Joint::Nose)[[0, 0]], 100.0);
    assert_eq!(track.quality.performer_switches_rejected, 1);
}

fn floats(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn label_filters_equal_scipy_on_the_dsp_mel_fixtures() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../dsp-mel/tests/fixtures/filters.json"
    );
    let fixtures: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let cfg = LabelConfig::default();
    // scipy.signal.filtfilt(*butter(4, 5, fs=30), x): the labels' step 1.
    let tf = dsp_mel::filters::Butterworth::lowpass(4, 5.0, 30.0)
        .unwrap()
        .transfer_function();
    let case = fixtures["filtfilt"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| {
            floats(&c["b"])
                .iter()
                .zip(&tf.b)
                .all(|(a, b)| (a - b).abs() < 1e-12)
        })
        .expect("a 4th-order 5 Hz / 30 Hz filtfilt case");
    let y = lowpass(&floats(&case["x"]), 30.0, &cfg).unwrap();
    let err = y
        .iter()
        .zip(floats(&case["y"]))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-9, "filtfilt differs from scipy by {err}");
    // scipy.ndimage.median_filter(v, 15, mode='nearest'): step 3, fed through step 2 by
    // integrating the fixture's input (so the velocity is the fixture's x).
    let case = fixtures["median_nearest"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["k"] == 15 && c["x"].as_array().unwrap().len() > 100)
        .unwrap();
    let x = floats(&case["x"]);
    let mut integral = vec![0.0];
    for v in &x {
        integral.push(integral[integral.len() - 1] + v);
    }
    let m = smoothed_velocity(&integral, cfg.velocity_median_window).unwrap();
    let err = m
        .iter()
        .zip(floats(&case["y"]))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-9, "median filter differs from scipy by {err}");
}
