//! `violin-skeleton pose-labels` end to end: the labels file and bad directories.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::Command;

use violin_skeleton::skeleton::{Joint, Motion, MotionFormat, PoseLayout};

fn cli() -> Command {
    Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
}

/// A COCO-18 OpenPose directory: a still body whose right wrist goes down for 40 frames,
/// up for 40, down for 40 (bow changes at frames 40 and 80).
fn write_strokes(dir: &Path, frames: usize) {
    std::fs::create_dir_all(dir).unwrap();
    for t in 0..frames {
        let wrist_y = match t {
            0..40 => 300.0 + 4.0 * t as f32,
            40..80 => 460.0 - 4.0 * (t - 40) as f32,
            _ => 300.0 + 4.0 * (t - 80) as f32,
        };
        let mut kp = vec![0.0f32; 18 * 3];
        for j in Joint::ALL {
            let k = j.openpose_index(PoseLayout::Coco18);
            let (x, y) = match j {
                Joint::RWrist => (500.0, wrist_y),
                _ => (
                    600.0 + 13.0 * j.index() as f32,
                    200.0 + 29.0 * j.index() as f32,
                ),
            };
            kp[3 * k..3 * k + 3].copy_from_slice(&[x, y, 0.9]);
        }
        let doc = serde_json::json!({"version": 1.3, "people": [{"pose_keypoints_2d": kp}]});
        std::fs::write(
            dir.join(format!("take_{t:012}_keypoints.json")),
            doc.to_string(),
        )
        .unwrap();
    }
}

#[test]
fn writes_labels_skeleton_and_quality() {
    let root = tempfile::tempdir().unwrap();
    let pose = root.path().join("pose");
    write_strokes(&pose, 120);
    let labels = root.path().join("labels.json");
    let csv = root.path().join("motion.csv");
    let st = cli()
        .args(["pose-labels", pose.to_str().unwrap(), "-o"])
        .arg(&labels)
        .arg("--skeleton-out")
        .arg(&csv)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&st.stderr);
    assert!(st.status.success(), "{stderr}");
    assert!(
        stderr.contains("120 frames (Coco18, 120 files) → 2 bow changes"),
        "{stderr}"
    );
    assert!(stderr.contains("timing:"), "{stderr}");

    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&labels).unwrap()).unwrap();
    assert_eq!(v["fps"], serde_json::json!(30));
    let changes: Vec<i64> = v["bow_change_frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_i64().unwrap())
        .collect();
    assert_eq!(changes.len(), 2);
    assert!(
        (changes[0] - 40).abs() <= 1 && (changes[1] - 80).abs() <= 1,
        "{changes:?}"
    );
    let skeleton = v["skeleton"].as_array().unwrap();
    assert_eq!(skeleton.len(), 120);
    assert!(skeleton
        .iter()
        .all(|row| row.as_array().unwrap().len() == 20));
    assert_eq!(v["quality"]["frames"], 120);
    assert_eq!(v["quality"]["layout"], "Coco18");
    assert_eq!(v["quality"]["long_gaps"], serde_json::json!([]));

    let motion = Motion::read(&csv, MotionFormat::Csv).unwrap();
    assert_eq!(motion.len(), 120);
    // The skeleton in labels.json is the same cleaned (centred) track.
    let r_wrist_y_40 = skeleton[40][2 * Joint::RWrist.index() + 1]
        .as_f64()
        .unwrap() as f32;
    assert_eq!(motion.joint(Joint::RWrist)[[40, 1]], r_wrist_y_40);

    // --quiet prints nothing; the threshold flags are honoured: nothing moves 5 px/frame
    // (--axis y) or 1 torso length per second (the wrist: 120 px/s, the torso 238 px).
    for flags in [
        ["--axis", "y", "--threshold-px", "5"],
        ["--axis", "bow", "--threshold", "1"],
    ] {
        let st = cli()
            .args(["--quiet", "pose-labels", pose.to_str().unwrap()])
            .args(flags)
            .arg("-o")
            .arg(&labels)
            .output()
            .unwrap();
        assert!(st.status.success());
        assert!(st.stderr.is_empty());
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&labels).unwrap()).unwrap();
        assert_eq!(v["bow_change_frames"], serde_json::json!([]), "{flags:?}");
    }
}

#[test]
fn schema_2_fields_frame_rates_and_resampling() {
    let root = tempfile::tempdir().unwrap();
    let pose = root.path().join("pose");
    write_strokes(&pose, 120);
    let labels = root.path().join("labels.json");
    // The same files said to be 60 fps: changes at the same frames, half the seconds; the
    // skeleton resampled to 30 fps has half the frames.
    let st = cli()
        .args([
            "pose-labels",
            pose.to_str().unwrap(),
            "--fps",
            "60",
            "--skeleton-fps",
            "30",
            "-o",
        ])
        .arg(&labels)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&st.stderr);
    assert!(st.status.success(), "{stderr}");
    assert!(stderr.contains("bowing arm: right"), "{stderr}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&labels).unwrap()).unwrap();
    assert_eq!(v["schema_version"], 2);
    assert_eq!(v["fps"], 60);
    assert_eq!(v["skeleton_fps"], 30);
    assert_eq!(v["bow_arm"], "right");
    assert_eq!(v["axis"], "bow");
    assert_eq!(v["skeleton"].as_array().unwrap().len(), 60);
    assert_eq!(v["confidence"].as_array().unwrap().len(), 120);
    let frames = v["bow_change_frames"].as_array().unwrap();
    let seconds = v["bow_change_s"].as_array().unwrap();
    assert_eq!(frames.len(), 2, "{v}");
    for (f, s) in frames.iter().zip(seconds) {
        assert!((f.as_f64().unwrap() / 60.0 - s.as_f64().unwrap()).abs() < 1e-3);
    }
    // --bow-arm left labels the other (still) wrist: no changes; --axis y is the original.
    for (flags, arm, axis) in [
        (["--bow-arm", "left"], "left", "bow"),
        (["--axis", "y"], "right", "y"),
    ] {
        let st = cli()
            .args(["pose-labels", pose.to_str().unwrap()])
            .args(flags)
            .arg("-o")
            .arg(&labels)
            .output()
            .unwrap();
        assert!(st.status.success());
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&labels).unwrap()).unwrap();
        assert_eq!(
            (v["bow_arm"].as_str(), v["axis"].as_str()),
            (Some(arm), Some(axis))
        );
        let n = v["bow_change_frames"].as_array().unwrap().len();
        assert_eq!(n, if arm == "left" { 0 } else { 2 }, "{flags:?}");
    }
    // A frame rate of 0 or below is a usage error (exit 2), on one line.
    for fps in ["0", "-25", "nan"] {
        for flag in ["--fps", "--skeleton-fps"] {
            let st = cli()
                .args(["pose-labels", pose.to_str().unwrap(), flag, fps, "-o"])
                .arg(root.path().join("never.json"))
                .output()
                .unwrap();
            assert_eq!(st.status.code(), Some(2), "{flag} {fps}");
            let err = String::from_utf8_lossy(&st.stderr);
            assert_eq!(err.lines().count(), 1, "{err}");
            assert!(err.contains(flag), "{err}");
        }
    }
    assert!(!root.path().join("never.json").exists());
}

#[test]
fn bad_directories_fail_with_one_line_and_no_output() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("labels.json");
    let empty = root.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let broken = root.path().join("broken");
    write_strokes(&broken, 30);
    std::fs::write(
        broken.join("take_000000000010_keypoints.json"),
        "{\"people\": [",
    )
    .unwrap();
    let missing = root.path().join("missing");
    for (dir, says) in [
        (&empty, "empty"),
        (&broken, "take_000000000010_keypoints.json"),
        (&missing, "not found"),
    ] {
        let st = cli()
            .args(["pose-labels", dir.to_str().unwrap(), "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(st.status.code(), Some(1), "{dir:?}");
        let err = String::from_utf8_lossy(&st.stderr);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.starts_with("error: ") && err.contains(says), "{err}");
        assert!(!out.exists(), "output written for {dir:?}");
    }
    // A bad flag value is a usage error (exit 2); an unknown skeleton extension fails early.
    let good = root.path().join("good");
    write_strokes(&good, 30);
    let st = cli()
        .args([
            "pose-labels",
            good.to_str().unwrap(),
            "--threshold-px",
            "-1",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(st.status.code(), Some(2));
    let st = cli()
        .args([
            "pose-labels",
            good.to_str().unwrap(),
            "--skeleton-out",
            "m.txt",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(st.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&st.stderr).contains("m.txt"));
    assert!(!out.exists());
}
