#![allow(clippy::unwrap_used, clippy::expect_used)]
//! The URMP loader on a tiny fixture made here: separated tracks `AuSep_K_vn_NAME.wav`, an
//! OpenPose directory `openpose_K_vn_NAME/` per violin track, other instruments ignored.

use std::path::Path;

use gru_baseline::data::DataLayout;
use gru_baseline::norm::TRUNK_JOINTS;
use gru_baseline::GruError;
use serde_json::json;
use skeleton::{Joint, PoseLayout};
use violin_train::gru_data::load_dataset;
use violin_train::TrainError;

const FRAMES: usize = 60;

fn write_wav(path: &Path, seconds: f32, rate: u32) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for i in 0..(seconds * rate as f32) as usize {
        let v = (i as f32 * 440.0 * std::f32::consts::TAU / rate as f32).sin() * 0.3;
        w.write_sample((v * 32767.0) as i16).unwrap();
    }
    w.finalize().unwrap();
}

/// A standing player: neck (600, 300), hips at y = 500 (torso 200 px), the right wrist
/// moving left-right with the frame number. BODY_25 layout.
fn pose(t: usize) -> Vec<f32> {
    let mut kp = vec![0f32; 25 * 3];
    let place = |kp: &mut Vec<f32>, j: Joint, x: f32, y: f32| {
        let i = j.openpose_index(PoseLayout::Body25);
        kp[3 * i] = x;
        kp[3 * i + 1] = y;
        kp[3 * i + 2] = 0.9;
    };
    let stroke = 40.0 * ((t as f32) * 0.2).sin();
    place(&mut kp, Joint::Nose, 600.0, 220.0);
    place(&mut kp, Joint::Neck, 600.0, 300.0);
    place(&mut kp, Joint::RShoulder, 540.0, 305.0);
    place(&mut kp, Joint::RElbow, 500.0, 380.0);
    place(&mut kp, Joint::RWrist, 520.0 + stroke, 420.0);
    place(&mut kp, Joint::LShoulder, 660.0, 305.0);
    place(&mut kp, Joint::LElbow, 700.0, 360.0);
    place(&mut kp, Joint::LWrist, 740.0, 300.0);
    place(&mut kp, Joint::RHip, 570.0, 500.0);
    place(&mut kp, Joint::LHip, 630.0, 500.0);
    kp
}

fn write_openpose(dir: &Path) {
    std::fs::create_dir_all(dir).unwrap();
    for t in 0..FRAMES {
        let doc = json!({"version": 1.3, "people": [{"pose_keypoints_2d": pose(t)}]});
        std::fs::write(
            dir.join(format!("vid_{t:012}_keypoints.json")),
            doc.to_string(),
        )
        .unwrap();
    }
}

fn fixture(root: &Path) {
    let piece = root.join("01_Jupiter_vn_vc");
    std::fs::create_dir_all(&piece).unwrap();
    write_wav(&piece.join("AuSep_1_vn_01_Jupiter.wav"), 2.5, 44_100);
    write_wav(&piece.join("AuSep_2_vc_01_Jupiter.wav"), 2.5, 44_100);
    write_openpose(&piece.join("openpose_1_vn_01_Jupiter"));
}

#[test]
fn loads_violin_tracks_with_their_skeletons() {
    let dir = tempfile::tempdir().unwrap();
    fixture(dir.path());
    let data = load_dataset(dir.path(), &|_, _| {}).unwrap();
    assert_eq!(data.layout, DataLayout::Urmp);
    assert_eq!(
        (data.train.len(), data.val.len(), data.test.len()),
        (1, 0, 0)
    );
    let seq = &data.train[0];
    assert!(
        seq.name.ends_with("AuSep_1_vn_01_Jupiter.wav"),
        "{}",
        seq.name
    );
    // 2.5 s of audio gives 76 mel frames; the 60 pose frames are shorter.
    assert_eq!(seq.mel_db.dim(), (FRAMES, 128));
    assert_eq!(seq.joints.dim(), (FRAMES, 20));
    // Torso: neck (600, 300) to the hips' midpoint (600, 500).
    assert!((seq.video.torso_px - 200.0).abs() < 1e-3, "{:?}", seq.video);
    // Pixels, not re-centred by pose-preproc: the centre is the mean of the trunk joints
    // (neck, shoulders, hips; they do not move in the fixture):
    // x = (600 + 540 + 660 + 570 + 630) / 5 = 600, y = (300 + 305 + 305 + 500 + 500) / 5 = 382.
    // (The mean of all ten joints would be y = 359, x ≈ 606: the arms must not move it.)
    assert!(
        (seq.video.center_px[0] - 600.0).abs() < 1e-3
            && (seq.video.center_px[1] - 382.0).abs() < 1e-3,
        "{:?}",
        seq.video
    );
    // So the normalised trunk joints average to zero in x and y; all joints do not.
    let trunk_mean = |d: usize| -> f32 {
        TRUNK_JOINTS
            .iter()
            .map(|j| seq.joints.column(2 * j.index() + d).mean().unwrap())
            .sum::<f32>()
            / TRUNK_JOINTS.len() as f32
    };
    assert!(
        trunk_mean(0).abs() < 1e-5 && trunk_mean(1).abs() < 1e-5,
        "{} {}",
        trunk_mean(0),
        trunk_mean(1)
    );
    let all_y: f32 = (0..10)
        .map(|j| seq.joints.column(2 * j + 1).mean().unwrap())
        .sum::<f32>()
        / 10.0;
    assert!(
        (all_y - (359.0 - 382.0) / 200.0).abs() < 1e-4,
        "mean of all joints' y {all_y}"
    );
    // The right wrist moves; the neck does not.
    let rw = seq.joints.column(2 * Joint::RWrist.index());
    let spread =
        rw.iter().cloned().fold(f32::MIN, f32::max) - rw.iter().cloned().fold(f32::MAX, f32::min);
    assert!(spread > 0.2, "right wrist x spread {spread}");
    let neck = seq.joints.column(2 * Joint::Neck.index());
    assert!(neck.iter().all(|v| (v - neck[0]).abs() < 1e-5));
}

#[test]
fn a_violin_track_without_poses_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    fixture(dir.path());
    let piece = dir.path().join("02_Sonata_vn");
    std::fs::create_dir_all(&piece).unwrap();
    write_wav(&piece.join("AuSep_1_vn_02_Sonata.wav"), 1.0, 22_050);
    let err = load_dataset(dir.path(), &|_, _| {}).unwrap_err();
    assert!(matches!(err, TrainError::Gru(GruError::Data { .. })));
    assert!(err.to_string().contains("openpose_1_vn_02_Sonata"), "{err}");
}

#[test]
fn a_folder_of_neither_layout_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("notes.txt"), "hello").unwrap();
    let err = load_dataset(dir.path(), &|_, _| {}).unwrap_err();
    assert!(err.to_string().contains("neither a corpus"), "{err}");
    let err = load_dataset(&dir.path().join("missing"), &|_, _| {}).unwrap_err();
    assert!(err.to_string().contains("not a directory"), "{err}");
    // An empty OpenPose directory fails in pose-preproc with its own typed error.
    let piece = dir.path().join("p");
    std::fs::create_dir_all(piece.join("openpose_1_vn_x")).unwrap();
    write_wav(&piece.join("AuSep_1_vn_x.wav"), 1.0, 22_050);
    assert!(matches!(
        load_dataset(dir.path(), &|_, _| {}),
        Err(TrainError::Pose(_))
    ));
}
