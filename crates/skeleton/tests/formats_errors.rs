//! Bad motion files and bad motions: each a typed error naming the file and the problem.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use ndarray::Array3;
use serde_json::json;
use skeleton::formats::{read_csv_from, read_json_from, read_npy_from, write_json};
use skeleton::{Joint, Motion, MotionFormat, SkeletonError};

fn names() -> Vec<&'static str> {
    Joint::ALL.iter().map(|j| j.name()).collect()
}

fn frames(t: usize) -> serde_json::Value {
    json!(vec![vec![[1.0, 2.0]; 10]; t])
}

fn json_err(v: serde_json::Value) -> SkeletonError {
    read_json_from(v.to_string().as_bytes()).unwrap_err()
}

#[test]
fn json_missing_fields_unknown_and_missing_joints() {
    let e = json_err(json!({"joints": names(), "frames": frames(2)}));
    assert!(
        matches!(&e, SkeletonError::MissingField { field, .. } if field == "fps"),
        "{e}"
    );
    let e = json_err(json!({"fps": 30, "frames": frames(2)}));
    assert!(
        matches!(&e, SkeletonError::MissingField { field, .. } if field == "joints"),
        "{e}"
    );
    let e = json_err(json!({"fps": 30, "joints": names()}));
    assert!(
        matches!(&e, SkeletonError::MissingField { field, .. } if field == "frames"),
        "{e}"
    );

    let mut unknown = names();
    unknown[3] = "r_knee";
    let e = json_err(json!({"fps": 30, "joints": unknown, "frames": frames(2)}));
    assert!(
        matches!(&e, SkeletonError::UnknownJoint { name, .. } if name == "r_knee"),
        "{e}"
    );
    let e = json_err(json!({"fps": 30, "joints": &names()[..9], "frames": frames(2)}));
    assert!(
        matches!(&e, SkeletonError::MissingJoint { name, .. } if name == "l_hip"),
        "{e}"
    );
    let mut twice = names();
    twice[9] = "nose";
    let e = json_err(json!({"fps": 30, "joints": twice, "frames": frames(2)}));
    assert!(e.to_string().contains("listed twice"), "{e}");
    let e = json_err(json!({"fps": -3, "joints": names(), "frames": frames(2)}));
    assert!(
        e.to_string().contains("fps must be a positive number"),
        "{e}"
    );
    let e = json_err(json!({"fps": 30, "joints": names(), "frames": frames(2), "units": "m"}));
    assert!(e.to_string().contains("pixels"), "{e}");
}

#[test]
fn json_wrong_shapes_nan_empty_and_truncated() {
    let mut nine = vec![vec![[1.0, 2.0]; 10]; 3];
    nine[2].pop();
    let e = json_err(json!({"fps": 30, "joints": names(), "frames": nine}));
    assert!(
        matches!(&e, SkeletonError::FileShape { what, .. } if what.contains("frame 2 has 9 points")),
        "{e}"
    );
    let three = vec![vec![[1.0, 2.0, 3.0]; 10]; 2];
    let e = json_err(json!({"fps": 30, "joints": names(), "frames": three}));
    assert!(matches!(e, SkeletonError::FileShape { .. }), "{e}");
    let e = json_err(
        json!({"fps": 30, "joints": names(), "frames": frames(2), "frames_3d": vec![vec![[0.0, 0.0, 0.0]; 10]; 3]}),
    );
    assert!(
        e.to_string()
            .contains("frames_3d has 3 frames, frames has 2"),
        "{e}"
    );

    let mut with_null = frames(2);
    with_null[1][4][1] = serde_json::Value::Null;
    let e = json_err(json!({"fps": 30, "joints": names(), "frames": with_null}));
    assert!(
        matches!(&e, SkeletonError::NonFinite { location, .. } if location.contains("frame 1, r_wrist, coordinate y")),
        "{e}"
    );
    let e = json_err(json!({"fps": 30, "joints": names(), "frames": []}));
    assert!(matches!(e, SkeletonError::Empty { .. }), "{e}");

    let mut bytes = Vec::new();
    write_json(
        &Motion::new(30.0, Array3::zeros((4, 10, 2))).unwrap(),
        &mut bytes,
    )
    .unwrap();
    let e = read_json_from(&bytes[..bytes.len() / 2]).unwrap_err();
    assert!(e.to_string().contains("not valid motion JSON"), "{e}");
}

#[test]
fn csv_errors() {
    let header = "frame,time_s,".to_string()
        + &Joint::ALL
            .iter()
            .map(|j| format!("{0}_x,{0}_y", j.name()))
            .collect::<Vec<_>>()
            .join(",");
    let row = |t: usize| format!("{t},{}", t as f64 / 30.0) + &",1.5".repeat(20);
    let err = |text: String| read_csv_from(text.as_bytes()).unwrap_err();

    let e = err(format!("{header}\n"));
    assert!(matches!(e, SkeletonError::Empty { .. }), "{e}");
    let e = err(String::new());
    assert!(matches!(e, SkeletonError::Empty { .. }), "{e}");
    let e = err(format!("{header}\n{}\n{}\n", row(0), &row(1)[..20]));
    assert!(
        matches!(&e, SkeletonError::FileShape { what, .. } if what.contains("line 3")),
        "{e}"
    );
    let e = err(format!("{header}\n{}\n", row(0).replace(",1.5", ",NaN")));
    assert!(
        matches!(&e, SkeletonError::NonFinite { location, .. } if location.contains("nose_x")),
        "{e}"
    );
    let e = err(format!(
        "{header}\n{}\n",
        row(0).replacen(",1.5", ",abc", 1)
    ));
    assert!(e.to_string().contains("\"abc\" is not a number"), "{e}");
    let e = err(format!("{},r_knee_x\n{},3\n", header, row(0)));
    assert!(
        matches!(&e, SkeletonError::UnknownJoint { name, .. } if name.contains("r_knee_x")),
        "{e}"
    );
    let e = err(format!(
        "{}\n{}\n",
        header.replace(",l_hip_y", ""),
        &row(0)[..row(0).len() - 4]
    ));
    assert!(
        matches!(&e, SkeletonError::MissingField { field, .. } if field == "l_hip_y"),
        "{e}"
    );
    let e = err(format!("{header}\n{}\n{}\n", row(0), row(2)));
    assert!(e.to_string().contains("frames must count 0, 1, 2"), "{e}");
    let e = err(format!(
        "{header}\n{}\n{}\n{}\n",
        row(0),
        row(1),
        row(2).replace(",0.0666", ",0.5")
    ));
    assert!(e.to_string().contains("evenly spaced"), "{e}");
}

#[test]
fn npy_errors() {
    let write = |a: &dyn Fn(&mut Vec<u8>)| {
        let mut bytes = Vec::new();
        a(&mut bytes);
        bytes
    };
    let wrong = write(&|b| {
        ndarray_npy::WriteNpyExt::write_npy(&ndarray::Array2::<f32>::zeros((5, 18)), b).unwrap()
    });
    let e = read_npy_from(wrong.as_slice(), 30.0).unwrap_err();
    assert!(
        matches!(&e, SkeletonError::FileShape { what, .. } if what.contains("(5, 18)")),
        "{e}"
    );
    let empty = write(&|b| {
        ndarray_npy::WriteNpyExt::write_npy(&ndarray::Array2::<f32>::zeros((0, 20)), b).unwrap()
    });
    assert!(matches!(
        read_npy_from(empty.as_slice(), 30.0).unwrap_err(),
        SkeletonError::Empty { .. }
    ));
    let mut nan = ndarray::Array2::<f32>::zeros((3, 20));
    nan[[1, 9]] = f32::NAN;
    let nan = write(&|b| ndarray_npy::WriteNpyExt::write_npy(&nan, b).unwrap());
    let e = read_npy_from(nan.as_slice(), 30.0).unwrap_err();
    assert!(
        matches!(&e, SkeletonError::NonFinite { location, .. } if location.contains("frame 1, joint r_wrist, coordinate y")),
        "{e}"
    );
    let ints = write(&|b| {
        ndarray_npy::WriteNpyExt::write_npy(&ndarray::Array2::<i32>::zeros((3, 20)), b).unwrap()
    });
    assert!(read_npy_from(ints.as_slice(), 30.0)
        .unwrap_err()
        .to_string()
        .contains("not a float32"));
    let good = write(&|b| {
        ndarray_npy::WriteNpyExt::write_npy(&ndarray::Array2::<f32>::zeros((3, 20)), b).unwrap()
    });
    assert!(read_npy_from(&good[..good.len() - 7], 30.0).is_err());
    assert!(matches!(
        read_npy_from(good.as_slice(), 0.0).unwrap_err(),
        SkeletonError::InvalidFps(_)
    ));
}

/// A damaged header that nests brackets deeply (found by `input-fuzz motion-npy`: a 3 kB
/// mutant nesting 18 `[` took over a second to parse) and an oversized header are refused by
/// name; a valid header still reads.
#[test]
fn npy_damaged_headers_are_refused() {
    let npy = |header: &str| {
        let mut h = header.to_string();
        while !(10 + h.len() + 1).is_multiple_of(64) {
            h.push(' ');
        }
        h.push('\n');
        let mut b = b"\x93NUMPY\x01\x00".to_vec();
        b.extend_from_slice(&(h.len() as u16).to_le_bytes());
        b.extend_from_slice(h.as_bytes());
        b.extend_from_slice(&[0u8; 4 * 20]);
        b
    };
    let good = npy("{'descr': '<f4', 'fortran_order': False, 'shape': (1, 20), }");
    assert_eq!(read_npy_from(good.as_slice(), 30.0).unwrap().len(), 1);
    let deep = format!(
        "{{'descr': '<f4', 'fortran_order': False,{}0)}}",
        "[".repeat(40)
    );
    let e = read_npy_from(npy(&deep).as_slice(), 30.0).unwrap_err();
    assert!(e.to_string().contains("nests brackets 41 deep"), "{e}");
    let mut long = b"\x93NUMPY\x02\x00".to_vec();
    long.extend_from_slice(&1_000_000u32.to_le_bytes());
    long.extend_from_slice(&[b' '; 64]);
    let e = read_npy_from(long.as_slice(), 30.0).unwrap_err();
    assert!(e.to_string().contains("header is 1000000 bytes"), "{e}");
}

#[test]
fn files_name_the_path_and_bad_motions_are_not_written() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.json");
    let e = Motion::read(&missing, MotionFormat::Json).unwrap_err();
    assert!(e.to_string().contains("missing.json"), "{e}");
    let empty = dir.path().join("empty.csv");
    std::fs::write(&empty, b"").unwrap();
    let e = Motion::read(&empty, MotionFormat::Csv).unwrap_err();
    assert!(
        e.to_string().contains("empty.csv") && e.to_string().contains("empty"),
        "{e}"
    );
    let garbage = dir.path().join("garbage.npy");
    std::fs::write(&garbage, b"not an npy file").unwrap();
    let e = Motion::read(&garbage, MotionFormat::Npy).unwrap_err();
    assert!(e.to_string().contains("garbage.npy"), "{e}");

    let mut track = Array3::zeros((3, 10, 2));
    track[[2, 7, 0]] = f32::NAN;
    let bad = Motion::new(30.0, track).unwrap();
    for (name, format) in [
        ("a.json", MotionFormat::Json),
        ("a.csv", MotionFormat::Csv),
        ("a.npy", MotionFormat::Npy),
        ("a", MotionFormat::OpenPose),
    ] {
        let path = dir.path().join(name);
        let e = bad.write(&path, format).unwrap_err();
        assert!(
            matches!(&e, SkeletonError::NonFinite { location, .. } if location.contains("frame 2, joint l_wrist, coordinate x")),
            "{name}: {e}"
        );
        assert!(e.to_string().contains(name), "{e}");
        assert!(!path.exists(), "{name} written despite the error");
    }
    let empty_motion = Motion::new(30.0, Array3::zeros((0, 10, 2))).unwrap();
    let e = empty_motion
        .write(dir.path().join("e.json"), MotionFormat::Json)
        .unwrap_err();
    assert!(matches!(e, SkeletonError::Empty { .. }), "{e}");
    let e = Motion::new(30.0, Array3::zeros((2, 10, 2)))
        .unwrap()
        .write(dir.path().join("no/such/dir.json"), MotionFormat::Json)
        .unwrap_err();
    assert!(e.to_string().contains("does not exist"), "{e}");
    assert!(MotionFormat::from_path(Path::new("x.txt")).is_err());
}

#[test]
fn plain_openpose_read_rejects_what_needs_preprocessing() {
    let dir = tempfile::tempdir().unwrap();
    let person = |n: usize, c: f32| json!({"pose_keypoints_2d": vec![c; 3 * n]});
    let write = |name: &str, v: serde_json::Value| {
        std::fs::write(dir.path().join(name), v.to_string()).unwrap()
    };
    write(
        "v_000000000000_keypoints.json",
        json!({"people": [person(25, 0.9)]}),
    );
    write(
        "v_000000000001_keypoints.json",
        json!({"people": [person(25, 0.9), person(25, 0.8)]}),
    );
    let e = Motion::read(dir.path(), MotionFormat::OpenPose).unwrap_err();
    assert!(
        e.to_string().contains("000000000001_keypoints.json") && e.to_string().contains("2 people"),
        "{e}"
    );
    write(
        "v_000000000001_keypoints.json",
        json!({"people": [person(18, 0.9)]}),
    );
    let e = Motion::read(dir.path(), MotionFormat::OpenPose).unwrap_err();
    assert!(e.to_string().contains("one layout per directory"), "{e}");
    write(
        "v_000000000001_keypoints.json",
        json!({"people": [person(25, 0.0)]}),
    );
    let e = Motion::read(dir.path(), MotionFormat::OpenPose).unwrap_err();
    assert!(e.to_string().contains("pose-preproc"), "{e}");
    write(
        "v_000000000001_keypoints.json",
        json!({"people": [person(20, 0.9)]}),
    );
    let e = Motion::read(dir.path(), MotionFormat::OpenPose).unwrap_err();
    assert!(matches!(e, SkeletonError::FileShape { .. }), "{e}");
    let empty = tempfile::tempdir().unwrap();
    assert!(matches!(
        Motion::read(empty.path(), MotionFormat::OpenPose).unwrap_err(),
        SkeletonError::Empty { .. }
    ));
}
