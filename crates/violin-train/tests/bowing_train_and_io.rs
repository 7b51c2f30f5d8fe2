//! Training (loss falls, checkpoints, resume), the corpus and URMP loaders, evaluation, and
//! the weights file's round trip and rejections.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use bowing_net::data::{Recording, Splits};
use bowing_net::{BowChangeDetector, TrainConfig};
use ndarray::Array2;
use net_core::checkpoint_path;
use net_core::rng::Rng;
use skeleton::{Joint, PoseLayout};
use violin_train::bowing_data::{load_dataset, load_urmp};

mod common;

/// Noise with a loud broadband click at every change: learnable in a few steps.
fn clicks(seed: u64, frames: usize) -> Recording {
    let mut rng = Rng::new(seed);
    let mut mel = Array2::from_shape_fn((frames, 128), |_| -60.0 + 5.0 * rng.normal() as f32);
    let mut changes = Vec::new();
    let mut t = 8;
    while t + 8 < frames {
        changes.push(t);
        mel.row_mut(t).mapv_inplace(|v| v + 30.0);
        t += 10 + (rng.next_u64() % 25) as usize;
    }
    Recording {
        name: format!("clicks{seed}"),
        group: "synthetic".into(),
        mel_db: mel,
        changes,
        onsets: Vec::new(),
        slurred: Vec::new(),
        strokes: Vec::new(),
        strings: Vec::new(),
    }
}

fn quick(epochs: usize) -> TrainConfig {
    TrainConfig {
        epochs,
        patience: 100,
        batch_sequences: 4,
        sequence_windows: 64,
        max_steps_per_epoch: Some(3),
        ..TrainConfig::default()
    }
}

#[test]
fn training_lowers_the_loss_and_resumes_from_the_checkpoint() {
    let data = Splits {
        train: (0..4).map(|s| clicks(s, 400)).collect(),
        val: vec![clicks(99, 300)],
        test: Vec::new(),
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.safetensors");
    let mut val_f1 = Vec::new();
    let report = bowing_net::train(&data, &quick(4), &out, false, &mut |p| {
        if let Some(f) = p.val_f1 {
            val_f1.push(f);
        }
    })
    .unwrap();
    let l = &report.epoch_losses;
    assert_eq!(l.len(), 4);
    assert!(l[3] < 0.9 * l[0], "loss should fall: {l:?}");
    assert_eq!(val_f1.len(), 4);
    assert!(checkpoint_path(&out).is_file());
    let det = BowChangeDetector::load(&out).unwrap();
    assert_eq!(det.decoder(), report.decoder);
    assert!(det.training_info().contains("\"epochs_run\":4"));
    let probs = det.frame_probabilities(data.val[0].mel_db.view()).unwrap();
    assert_eq!(probs.len(), 300);
    assert!(probs.iter().all(|p| (0.0..=1.0).contains(p)));

    let resumed = bowing_net::train(&data, &quick(5), &out, true, &mut |_| {}).unwrap();
    assert_eq!(resumed.epochs_run, 5);
    assert_eq!(&resumed.epoch_losses[..4], &l[..]);
    // Same seed, fresh run: bit-identical losses (seeded order, initialisation, dropout).
    let again = bowing_net::train(
        &data,
        &quick(4),
        &dir.path().join("c.safetensors"),
        false,
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(again.epoch_losses, report.epoch_losses);
}

#[test]
fn training_rejects_unusable_data() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.safetensors");
    let no_val = Splits {
        train: vec![clicks(1, 200)],
        ..Splits::default()
    };
    assert!(
        bowing_net::train(&no_val, &quick(1), &out, false, &mut |_| {})
            .unwrap_err()
            .to_string()
            .contains("validation")
    );
    let mut nan = clicks(2, 200);
    nan.mel_db[[10, 10]] = f32::NAN;
    let bad = Splits {
        train: vec![nan],
        val: vec![clicks(3, 200)],
        test: Vec::new(),
    };
    assert!(bowing_net::train(&bad, &quick(1), &out, false, &mut |_| {})
        .unwrap_err()
        .to_string()
        .contains("non-finite"));
    let mut silent = clicks(4, 200);
    silent.changes.clear();
    let none = Splits {
        train: vec![silent],
        val: vec![clicks(5, 200)],
        test: Vec::new(),
    };
    assert!(
        bowing_net::train(&none, &quick(1), &out, false, &mut |_| {})
            .unwrap_err()
            .to_string()
            .contains("no bow change")
    );
    // Resume without a checkpoint names the missing file.
    let data = Splits {
        train: vec![clicks(6, 200)],
        val: vec![clicks(7, 200)],
        test: Vec::new(),
    };
    let e = bowing_net::train(&data, &quick(1), &out, true, &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("b.ckpt.safetensors"), "{e}");
}

#[test]
fn corpus_layout_loads_exact_labels_and_evaluates() {
    let dir = tempfile::tempdir().unwrap();
    common::build_tiny_corpus(dir.path(), 0);
    let data = load_dataset(dir.path(), &|_, _| {}).unwrap();
    assert!(!data.train.is_empty() && !data.val.is_empty() && !data.test.is_empty());
    for r in data.train.iter().chain(&data.val).chain(&data.test) {
        assert_eq!(r.mel_db.ncols(), 128);
        assert!(!r.changes.is_empty());
        assert!(r.changes.windows(2).all(|w| w[0] < w[1]));
        // Bow changes are note onsets; slurred changes are the other onsets.
        assert!(r.changes.iter().all(|c| r.onsets.contains(c)));
        assert!(r
            .slurred
            .iter()
            .all(|s| r.onsets.contains(s) && !r.changes.contains(s)));
        assert_eq!(r.group, "builtin");
    }
    let eval = bowing_net::metrics::evaluate(&BowChangeDetector::pretrained().unwrap(), &data.test)
        .unwrap();
    let c = eval.all.changes_3;
    let truth: usize = data.test.iter().map(|r| r.changes.len()).sum();
    assert_eq!(c.true_positives + c.false_negatives, truth);
    assert_eq!(eval.by_group.len(), 1);
    // A missing label file is an error naming it.
    let item = dir.path().join("items/00000/bowchanges.txt");
    std::fs::remove_file(&item).unwrap();
    let e = load_dataset(dir.path(), &|_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("bowchanges.txt"), "{e}");
}

fn write_tone(path: &Path, seconds: f32) {
    let rate = 22_050u32;
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for i in 0..(seconds * rate as f32) as usize {
        let t = i as f32 / rate as f32;
        w.write_sample((0.3 * (2.0 * std::f32::consts::PI * 440.0 * t).sin() * 32767.0) as i16)
            .unwrap();
    }
    w.finalize().unwrap();
}

/// One OpenPose BODY_25 file per frame; the right wrist strokes up and down, 30 frames per
/// stroke (bow changes at 30, 60, 90, 120).
fn write_openpose(dir: &Path, frames: usize) {
    std::fs::create_dir_all(dir).unwrap();
    for f in 0..frames {
        let mut kp = vec![0.0f32; 25 * 3];
        for (k, j) in Joint::ALL.iter().enumerate() {
            let i = j.openpose_index(PoseLayout::Body25);
            let (mut x, mut y) = (300.0 + 20.0 * k as f32, 200.0 + 15.0 * k as f32);
            if *j == Joint::RWrist {
                let phase = f % 60;
                let dy = if phase < 30 {
                    phase as f32
                } else {
                    (60 - phase) as f32
                };
                y += 4.0 * dy;
                x += 2.0 * dy;
            }
            kp[3 * i] = x;
            kp[3 * i + 1] = y;
            kp[3 * i + 2] = 0.9;
        }
        let json = serde_json::json!({"version": 1.3, "people": [{"pose_keypoints_2d": kp}]});
        std::fs::write(
            dir.join(format!("take_{f:012}_keypoints.json")),
            json.to_string(),
        )
        .unwrap();
    }
}

#[test]
fn urmp_layout_takes_labels_from_the_skeleton() {
    let dir = tempfile::tempdir().unwrap();
    let piece = dir.path().join("01_Test_vn_vc");
    std::fs::create_dir_all(&piece).unwrap();
    write_tone(&piece.join("AuSep_1_vn_01_Test.wav"), 5.0);
    write_tone(&piece.join("AuSep_2_vc_01_Test.wav"), 5.0); // not a violin: ignored
    write_openpose(&piece.join("openpose_1_vn_01_Test"), 150);
    let data = load_urmp(dir.path(), &Default::default(), &|_, _| {}).unwrap();
    let all: Vec<&Recording> = data
        .train
        .iter()
        .chain(&data.val)
        .chain(&data.test)
        .collect();
    assert_eq!(all.len(), 1);
    let r = all[0];
    assert_eq!(r.group, "urmp");
    assert_eq!(r.mel_db.nrows(), 150);
    assert!(r.onsets.is_empty());
    let expected = [30usize, 60, 90, 120];
    assert_eq!(r.changes.len(), expected.len(), "{:?}", r.changes);
    for (c, e) in r.changes.iter().zip(expected) {
        assert!(c.abs_diff(e) <= 2, "{:?}", r.changes);
    }
    // A violin track without its pose directory is an error naming the expected folder.
    write_tone(&piece.join("AuSep_3_vn_01_Test.wav"), 1.0);
    let e = load_urmp(dir.path(), &Default::default(), &|_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("openpose_3_vn_01_Test"), "{e}");
}

#[test]
fn weights_round_trip_and_bad_files_are_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let det = BowChangeDetector::pretrained().unwrap();
    let path = dir.path().join("w.safetensors");
    det.save(&path).unwrap();
    let back = BowChangeDetector::load(&path).unwrap();
    let mel = clicks(5, 200).mel_db;
    assert_eq!(
        back.frame_probabilities(mel.view()).unwrap(),
        det.frame_probabilities(mel.view()).unwrap()
    );
    assert_eq!(back.decoder(), det.decoder());

    let bytes = std::fs::read(&path).unwrap();
    let cut = dir.path().join("cut.safetensors");
    std::fs::write(&cut, &bytes[..bytes.len() - 100]).unwrap();
    let e = BowChangeDetector::load(&cut).unwrap_err().to_string();
    assert!(
        e.contains("cut.safetensors") && e.contains("truncated"),
        "{e}"
    );

    // Same tensors, other version / other network / shapes that do not fit the config.
    let file = net_core::file::decode(&bytes, &path).unwrap();
    let tensors: Vec<_> = file.tensors.clone().into_iter().collect();
    let rewrite = |key: &str, value: &str| {
        let mut meta = file.metadata.clone();
        meta.insert(key.to_string(), value.to_string());
        net_core::file::encode(&tensors, meta).unwrap()
    };
    let e = BowChangeDetector::from_bytes(&rewrite("format_version", "99"), Path::new("v.st"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("version 99"), "{e}");
    let e = BowChangeDetector::from_bytes(
        &rewrite("format", "violin-skeleton/emotion-net"),
        Path::new("e.st"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("emotion-net"), "{e}");
    let mut cfg = det.net().config().clone();
    cfg.dense_units = [32, 128];
    let e = BowChangeDetector::from_bytes(
        &rewrite("config", &serde_json::to_string(&cfg).unwrap()),
        Path::new("s.st"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("\"dense1.") && e.contains("shape"), "{e}");
    let e = BowChangeDetector::load(&dir.path().join("missing.safetensors"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.safetensors"), "{e}");
}
