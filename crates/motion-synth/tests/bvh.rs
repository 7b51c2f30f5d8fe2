//! BVH export: written, parsed back, forward kinematics reproduces the 3-D joints.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use motion_synth::{synthesize, SynthConfig};
use ndarray::Array3;
use performance::{ArousalCurve, Performance};
use skeleton::formats::bvh::{joint_for, parse_bvh, write_bvh, write_bvh_file};
use skeleton::{Joint, Motion, SkeletonError};

fn motion() -> Motion {
    // Crosses all four strings, shifts, changes bow often, leans and sways.
    let midi = [55, 62, 69, 76, 81, 88, 79, 71, 64, 57];
    let mut b = Performance::builder(5.0);
    for (i, m) in midi.iter().enumerate() {
        b = b.note(i as f64 * 0.5, i as f64 * 0.5 + 0.45, *m);
    }
    let perf = b
        .bow_changes((1..10).map(|i| i as f64 * 0.5).collect())
        .downbeats(vec![0.0, 2.0, 4.0])
        .arousal(ArousalCurve::deam(
            (0..10).map(|i| -0.9 + 0.2 * i as f32).collect(),
        ))
        .build()
        .unwrap();
    synthesize(&perf, &SynthConfig::default()).unwrap()
}

/// The motion's core tracks only (as read from a file without a performer).
fn core_only(m: &Motion) -> Motion {
    Motion::new(m.fps(), m.frames().clone())
        .unwrap()
        .with_3d(m.frames_3d().unwrap().clone())
        .unwrap()
}

#[test]
fn performer_bvh_has_fingers_violin_and_bow_and_reproduces_every_point() {
    use skeleton::{BodyPoint, Finger, InstrumentPart, PerformerPart};
    let m = motion();
    let mut bytes = Vec::new();
    write_bvh(&m, &mut bytes).unwrap();
    let bvh = parse_bvh(std::str::from_utf8(&bytes).unwrap()).unwrap();
    assert!(bvh.joints.len() >= 40, "{} joints", bvh.joints.len());
    assert_eq!(bvh.frames.len(), m.len());
    let p = m.performer().unwrap();
    let get = |part: PerformerPart, f: usize, k: usize| {
        let t = p.track_3d(part).unwrap();
        [t[[f, k, 0]], t[[f, k, 1]], t[[f, k, 2]]].map(f64::from)
    };
    let checks: Vec<(&str, PerformerPart, usize)> = vec![
        ("Hips", PerformerPart::Body, BodyPoint::MidHip.index()),
        ("Nose", PerformerPart::Body, BodyPoint::Nose.index()),
        ("LeftEar", PerformerPart::Body, BodyPoint::LEar.index()),
        ("RightWrist", PerformerPart::Body, BodyPoint::RWrist.index()),
        ("LeftLeg", PerformerPart::Body, BodyPoint::LKnee.index()),
        ("RightHeel", PerformerPart::Body, BodyPoint::RHeel.index()),
        (
            "LeftHandIndex4",
            PerformerPart::LeftHand,
            Finger::Index.tip(),
        ),
        (
            "LeftHandPinky4",
            PerformerPart::LeftHand,
            Finger::Pinky.tip(),
        ),
        (
            "LeftHandThumb2",
            PerformerPart::LeftHand,
            Finger::Thumb.point(2),
        ),
        (
            "RightHandMiddle3",
            PerformerPart::RightHand,
            Finger::Middle.point(3),
        ),
        (
            "Violin",
            PerformerPart::Instrument,
            InstrumentPart::ViolinEndButton.index(),
        ),
        (
            "StringENut",
            PerformerPart::Instrument,
            InstrumentPart::StringAtNut(3).index(),
        ),
        (
            "Bow",
            PerformerPart::Instrument,
            InstrumentPart::BowFrog.index(),
        ),
        (
            "BowHairTip",
            PerformerPart::Instrument,
            InstrumentPart::BowHairTip.index(),
        ),
    ];
    let mut worst = 0.0f64;
    for f in (0..m.len()).step_by(7) {
        let fk = bvh.forward_kinematics(f).unwrap();
        for (name, part, k) in &checks {
            let at = fk[bvh.joint_index(name).unwrap_or_else(|| panic!("{name}"))];
            let want = get(*part, f, *k);
            for c in 0..3 {
                worst = worst.max((at[c] / 100.0 - want[c]).abs());
            }
        }
    }
    assert!(worst < 1e-3, "forward kinematics off by {worst} m");
    // Y up: the nose is above the hips in the rest pose.
    let nose = bvh.forward_kinematics(0).unwrap()[bvh.joint_index("Nose").unwrap()];
    assert!(nose[1] > 150.0, "{nose:?}");
}

#[test]
fn written_bvh_parses_back_and_reproduces_the_joints() {
    let m = core_only(&motion());
    let mut bytes = Vec::new();
    write_bvh(&m, &mut bytes).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    assert!(text.contains("Frame Time: 0.0333333\n"));
    assert!(text.contains("CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"));
    let bvh = parse_bvh(&text).unwrap();
    assert_eq!(bvh.channel_count(), 6 + 11 * 3);
    assert_eq!(bvh.frames.len(), m.len());
    assert!((bvh.frame_time_s - 1.0 / 30.0).abs() < 1e-6);
    for name in [
        "Hips",
        "Spine",
        "Neck",
        "Head",
        "RightShoulder",
        "RightElbow",
        "RightWrist",
        "LeftShoulder",
        "LeftElbow",
        "LeftWrist",
    ] {
        assert!(bvh.joint_index(name).is_some(), "{name}");
    }
    // Hierarchy as specified.
    let parent = |n: &str| {
        bvh.joints[bvh.joint_index(n).unwrap()]
            .parent
            .map(|p| bvh.joints[p].name.clone())
    };
    assert_eq!(parent("Spine").as_deref(), Some("Hips"));
    assert_eq!(parent("Neck").as_deref(), Some("Spine"));
    assert_eq!(parent("Head").as_deref(), Some("Neck"));
    assert_eq!(parent("RightShoulder").as_deref(), Some("Spine"));
    assert_eq!(parent("RightWrist").as_deref(), Some("RightElbow"));
    assert_eq!(parent("LeftElbow").as_deref(), Some("LeftShoulder"));
    // OFFSETs are the rig's bone lengths in centimetres.
    let offset = |n: &str| bvh.joints[bvh.joint_index(n).unwrap()].offset;
    assert!((offset("RightElbow")[0] + 30.0).abs() < 0.01);
    assert!((offset("LeftWrist")[0] - 27.0).abs() < 0.01);

    let track = m.frames_3d().unwrap();
    let mut worst = 0.0f64;
    for f in 0..m.len() {
        let fk = bvh.forward_kinematics(f).unwrap();
        for j in Joint::ALL {
            let p = fk[bvh.joint_index(joint_for(j)).unwrap()];
            for c in 0..3 {
                worst = worst.max((p[c] / 100.0 - f64::from(track[[f, j.index(), c]])).abs());
            }
        }
    }
    assert!(worst < 0.001, "forward kinematics off by {worst} m");
}

#[test]
fn file_variant_is_atomic_and_errors_are_typed() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("take.bvh");
    let m = motion();
    write_bvh_file(&m, &path).unwrap();
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        names,
        vec![std::ffi::OsString::from("take.bvh")],
        "no temporary file left"
    );
    assert_eq!(
        parse_bvh(&std::fs::read_to_string(&path).unwrap())
            .unwrap()
            .frames
            .len(),
        m.len()
    );

    let flat = Motion::new(30.0, Array3::zeros((3, 10, 2))).unwrap();
    assert!(matches!(
        write_bvh(&flat, Vec::new()),
        Err(SkeletonError::MissingTrack { .. })
    ));
    let mut nan = Array3::<f32>::zeros((3, 10, 3));
    nan[[1, 2, 0]] = f32::NAN;
    let bad = Motion::new(30.0, Array3::zeros((3, 10, 2)))
        .unwrap()
        .with_3d(nan)
        .unwrap();
    assert!(write_bvh(&bad, Vec::new()).is_err());
    let missing_dir = dir.path().join("nope").join("x.bvh");
    let e = write_bvh_file(&m, &missing_dir).unwrap_err().to_string();
    assert!(e.contains("nope"), "{e}");
}
