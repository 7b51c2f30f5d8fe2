//! Every motion format written and read back, and the files' exact schemas.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use ndarray::{Array3, Axis, ShapeBuilder};
use skeleton::formats::{
    openpose_frame_number, read_csv_from, read_json_from, read_npy_from, write_csv, write_json,
    write_npy,
};
use skeleton::{Joint, Motion, MotionFormat, OpenPoseOptions, PoseLayout};

/// A deterministic motion with non-round values (exercises float formatting).
fn motion(frames: usize, fps: f64) -> Motion {
    let track = Array3::from_shape_fn((frames, 10, 2), |(t, j, c)| {
        (t as f32 * 1.37 + j as f32 * 41.3 + c as f32 * 0.1 + 0.123_456_7).sin() * 250.0 + 400.0
    });
    Motion::new(fps, track).unwrap()
}

fn full_motion(frames: usize) -> Motion {
    let f3 = Array3::from_shape_fn((frames, 10, 3), |(t, j, c)| {
        (t * 31 + j * 7 + c) as f32 * 0.001 - 0.2
    });
    let i2 = Array3::from_shape_fn((frames, 4, 2), |(t, p, c)| (t + p * 3 + c) as f32 * 1.5);
    let i3 = Array3::from_shape_fn((frames, 4, 3), |(t, p, c)| (t + p + c) as f32 * -0.01);
    motion(frames, 30.0)
        .with_3d(f3)
        .unwrap()
        .with_instrument(i2)
        .unwrap()
        .with_instrument_3d(i3)
        .unwrap()
        .with_image_size(1280, 720)
}

#[test]
fn every_format_round_trips_through_files() {
    let dir = tempfile::tempdir().unwrap();
    let m = motion(37, 30.0);
    for (name, format) in [
        ("m.json", MotionFormat::Json),
        ("m.csv", MotionFormat::Csv),
        ("m.npy", MotionFormat::Npy),
        ("m_pose", MotionFormat::OpenPose),
    ] {
        let path = dir.path().join(name);
        assert_eq!(MotionFormat::from_path(&path).unwrap(), format);
        m.write(&path, format).unwrap();
        let back = Motion::read(&path, format).unwrap();
        assert_eq!(back, m, "{name}");
    }
    // Nothing but the four outputs is left in the directory (no temporaries).
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 4);
}

#[test]
fn json_keeps_every_track_and_the_schema() {
    let m = full_motion(5);
    let mut bytes = Vec::new();
    write_json(&m, &mut bytes).unwrap();
    assert_eq!(read_json_from(bytes.as_slice()).unwrap(), m);
    let v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    assert_eq!(v["fps"], serde_json::json!(30));
    assert_eq!(v["units"], "px");
    assert_eq!(v["image_size"], serde_json::json!([1280, 720]));
    let names: Vec<&str> = Joint::ALL.iter().map(|j| j.name()).collect();
    assert_eq!(v["joints"], serde_json::json!(names));
    assert_eq!(v["frames"].as_array().unwrap().len(), 5);
    assert_eq!(v["frames"][0].as_array().unwrap().len(), 10);
    assert_eq!(v["frames"][0][0].as_array().unwrap().len(), 2);
    assert_eq!(v["frames_3d"][4][9].as_array().unwrap().len(), 3);
    assert_eq!(
        v["instrument_points"],
        serde_json::json!(["bow_frog", "bow_tip", "violin_scroll", "violin_body"])
    );
    assert_eq!(v["instrument"][0].as_array().unwrap().len(), 4);
    assert_eq!(v["instrument_3d"][0][0].as_array().unwrap().len(), 3);

    // Optional tracks are absent when the motion has none; a fractional fps stays a float.
    let plain = motion(2, 29.97);
    let mut bytes = Vec::new();
    write_json(&plain, &mut bytes).unwrap();
    let v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    for key in [
        "frames_3d",
        "image_size",
        "instrument_points",
        "instrument",
        "instrument_3d",
    ] {
        assert!(v.get(key).is_none(), "{key} written without data");
    }
    assert_eq!(v["fps"], serde_json::json!(29.97));
    assert_eq!(read_json_from(bytes.as_slice()).unwrap().fps(), 29.97);
}

#[test]
fn json_joints_are_read_by_name_in_any_order() {
    let m = motion(3, 30.0);
    // Reverse the joint order in the file.
    let names: Vec<&str> = Joint::ALL.iter().rev().map(|j| j.name()).collect();
    let frames: Vec<Vec<[f32; 2]>> = m
        .frames()
        .outer_iter()
        .map(|f| f.outer_iter().rev().map(|p| [p[0], p[1]]).collect())
        .collect();
    let text =
        serde_json::json!({"fps": 30, "joints": names, "frames": frames, "extra": "ignored"});
    let back = read_json_from(text.to_string().as_bytes()).unwrap();
    assert_eq!(back, m);
}

#[test]
fn csv_schema_and_frame_rate() {
    let m = motion(4, 25.0);
    let mut bytes = Vec::new();
    write_csv(&m, &mut bytes).unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("frame,time_s,nose_x,nose_y,neck_x,neck_y,r_shoulder_x"));
    assert!(header.ends_with("r_hip_x,r_hip_y,l_hip_x,l_hip_y"));
    assert_eq!(header.split(',').count(), 22);
    assert!(lines.nth(1).unwrap().starts_with("1,0.04,"));
    assert_eq!(read_csv_from(bytes.as_slice()).unwrap(), m);
    for fps in [29.97, 60.0, 12.5] {
        let m = motion(50, fps);
        let mut bytes = Vec::new();
        write_csv(&m, &mut bytes).unwrap();
        assert!((read_csv_from(bytes.as_slice()).unwrap().fps() - fps).abs() < 1e-9);
    }
    // Columns may come in any order; a single row is read at 30 fps; CRLF is fine.
    let mut cols: Vec<String> = header.split(',').map(str::to_string).collect();
    let row: Vec<String> = (0..22)
        .map(|i| if i < 2 { "0".into() } else { format!("{i}.5") })
        .collect();
    cols.swap(2, 21);
    let text = format!("{}\r\n{}\r\n", cols.join(","), row.join(","));
    let one = read_csv_from(text.as_bytes()).unwrap();
    assert_eq!(one.fps(), 30.0);
    assert_eq!(one.frames()[[0, 9, 1]], 2.5); // l_hip_y read from the third column
    assert_eq!(one.frames()[[0, 0, 0]], 21.5); // nose_x from the last
}

#[test]
fn npy_is_float32_t_by_20_and_other_layouts_are_accepted() {
    let m = motion(6, 30.0);
    let mut bytes = Vec::new();
    write_npy(&m, &mut bytes).unwrap();
    let flat: ndarray::Array2<f32> = ndarray_npy::ReadNpyExt::read_npy(bytes.as_slice()).unwrap();
    assert_eq!(flat.dim(), (6, 20));
    assert_eq!(flat[[2, 9]], m.frames()[[2, 4, 1]]); // r_wrist y
    let back = read_npy_from(bytes.as_slice(), 60.0).unwrap();
    assert_eq!(back.fps(), 60.0);
    assert_eq!(back.frames(), m.frames());
    // float64 (T, 10, 2) is read too.
    let f64_3d = m.frames().mapv(f64::from);
    let mut bytes = Vec::new();
    ndarray_npy::WriteNpyExt::write_npy(&f64_3d, &mut bytes).unwrap();
    assert_eq!(read_npy_from(bytes.as_slice(), 30.0).unwrap(), m);
    // A transposed (non-standard layout) motion is written in the right order.
    let mut swapped = Array3::zeros((6, 10, 2).f());
    swapped.assign(m.frames());
    assert!(!swapped.is_standard_layout());
    let m2 = Motion::new(30.0, swapped).unwrap();
    let mut bytes = Vec::new();
    write_npy(&m2, &mut bytes).unwrap();
    assert_eq!(read_npy_from(bytes.as_slice(), 30.0).unwrap(), m);
}

#[test]
fn openpose_files_follow_openpose_schema_in_both_layouts() {
    let dir = tempfile::tempdir().unwrap();
    let m = motion(3, 30.0);
    for layout in [PoseLayout::Body25, PoseLayout::Coco18] {
        let out = dir.path().join(format!("{layout:?}"));
        let options = OpenPoseOptions {
            layout,
            name_prefix: "take1".into(),
        };
        m.write_openpose(&out, &options).unwrap();
        let mut names: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        names.sort();
        assert_eq!(
            names,
            (0..3)
                .map(|t| format!("take1_{t:012}_keypoints.json"))
                .collect::<Vec<_>>()
        );
        assert_eq!(openpose_frame_number(&names[2]), Some(2));
        let text = std::fs::read_to_string(out.join(&names[1])).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["version"], serde_json::json!(1.3));
        let person = &v["people"][0];
        assert_eq!(person["person_id"], serde_json::json!([-1]));
        for key in ["face_keypoints_2d", "pose_keypoints_3d"] {
            assert_eq!(person[key], serde_json::json!([]), "{key}");
        }
        // No hands in the motion: 21 points each, all with confidence 0.
        for key in ["hand_left_keypoints_2d", "hand_right_keypoints_2d"] {
            let hand: Vec<f32> = serde_json::from_value(person[key].clone()).unwrap();
            assert_eq!(hand, vec![0.0; 63], "{key}");
        }
        let kp: Vec<f32> = serde_json::from_value(person["pose_keypoints_2d"].clone()).unwrap();
        assert_eq!(kp.len(), 3 * layout.keypoint_count());
        let frame = m.frames().index_axis(Axis(0), 1);
        for j in Joint::ALL {
            let k = j.openpose_index(layout);
            assert_eq!(
                &kp[3 * k..3 * k + 3],
                &[frame[[j.index(), 0]], frame[[j.index(), 1]], 1.0]
            );
        }
        let ours: Vec<usize> = Joint::ALL
            .iter()
            .map(|j| j.openpose_index(layout))
            .collect();
        for k in (0..layout.keypoint_count()).filter(|k| !ours.contains(k)) {
            if layout == PoseLayout::Body25 && k == 8 {
                // MidHip: the mean of the hips, confident.
                let (r, l) = (Joint::RHip.index(), Joint::LHip.index());
                assert!((kp[24] - 0.5 * (frame[[r, 0]] + frame[[l, 0]])).abs() < 1e-3);
                assert!((kp[25] - 0.5 * (frame[[r, 1]] + frame[[l, 1]])).abs() < 1e-3);
                assert_eq!(kp[26], 1.0);
            } else {
                assert_eq!(&kp[3 * k..3 * k + 3], &[0.0, 0.0, 0.0], "keypoint {k}");
            }
        }
        assert_eq!(Motion::read_openpose(&out, 30.0).unwrap(), m);
    }
}

#[test]
fn openpose_directory_is_replaced_atomically() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pose");
    motion(5, 30.0).write(&out, MotionFormat::OpenPose).unwrap();
    let shorter = motion(2, 30.0);
    shorter.write(&out, MotionFormat::OpenPose).unwrap();
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 2);
    assert_eq!(Motion::read(&out, MotionFormat::OpenPose).unwrap(), shorter);
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}
