//! Training on a tiny corpus, inference, weights files and the DEAM loader.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use emotion_net::data::{ArousalSplits, ArousalTrack};
use emotion_net::{ArousalEstimator, TrainConfig};
use ndarray::Array2;
use violin_train::emotion_data::{
    load_corpus_with, load_dataset, load_deam, read_deam_arousal, CorpusTarget, DEAM_AROUSAL_CSV,
};

mod common;

fn tiny_corpus(dir: &Path) {
    common::build_tiny_corpus(dir, 0);
}

fn quick_config(epochs: usize) -> TrainConfig {
    TrainConfig {
        epochs,
        patience: 100,
        batch_windows: 8,
        max_steps_per_epoch: Some(4),
        learning_rate: 1e-2,
        ..TrainConfig::default()
    }
}

#[test]
fn trains_on_a_tiny_corpus_and_round_trips_weights() {
    let dir = tempfile::tempdir().unwrap();
    tiny_corpus(dir.path());
    let data = load_dataset(dir.path(), &|_, _| {}).unwrap();
    assert!(!data.train.is_empty() && !data.val.is_empty() && !data.test.is_empty());
    for t in data.train.iter().chain(&data.val) {
        assert_eq!(t.mel_db.ncols(), 64);
        assert_eq!(t.first_frame, 0);
        // 2 Hz targets for a ~10 s item, at most as many as mel frames.
        assert!(
            (15..=t.mel_db.nrows()).contains(&t.arousal.len()),
            "{} targets",
            t.arousal.len()
        );
        assert!(t.arousal.iter().all(|a| (-1.0..=1.0).contains(a)));
    }
    // The recomputed proxy is what the corpus wrote (a corpus made with this build).
    let written = load_corpus_with(dir.path(), CorpusTarget::File, &|_, _| {}).unwrap();
    for (a, b) in data.train.iter().zip(&written.train) {
        assert_eq!(a.arousal.len(), b.arousal.len());
        assert!(a
            .arousal
            .iter()
            .zip(&b.arousal)
            .all(|(x, y)| (x - y).abs() < 1e-5));
    }
    let out = dir.path().join("emotion.safetensors");
    let mut losses = Vec::new();
    let report = emotion_net::train(&data, &quick_config(6), &out, false, &mut |p| {
        if p.val_r.is_some() {
            losses.push(p.loss);
        }
    })
    .unwrap();
    assert_eq!(report.epochs_run, 6);
    assert_eq!(losses.len(), 6);
    assert!(
        losses[5] < losses[0],
        "training loss should fall: {losses:?}"
    );

    // Round trip: the saved file predicts exactly what a reload predicts.
    let est = ArousalEstimator::load(&out).unwrap();
    let mel = &data.test[0].mel_db;
    let a = est.predict(mel.view()).unwrap();
    assert_eq!(a.len(), mel.nrows());
    assert!(a.iter().all(|v| (-1.0..=1.0).contains(v)));
    let again = ArousalEstimator::from_bytes(&est.to_bytes().unwrap(), Path::new("mem")).unwrap();
    assert_eq!(again.predict(mel.view()).unwrap(), a);
    assert!(
        est.training_info().contains("\"epochs_run\":6"),
        "{}",
        est.training_info()
    );

    // Resume continues from the checkpoint to the new epoch count.
    let resumed = emotion_net::train(&data, &quick_config(7), &out, true, &mut |_| {}).unwrap();
    assert_eq!(resumed.epochs_run, 7);
    assert_eq!(resumed.epoch_losses.len(), 7);
    assert_eq!(&resumed.epoch_losses[..6], &report.epoch_losses[..]);

    // An item without its performance cannot give the proxy: the error names the file.
    let item = dir.path().join("items/00000/performance.json");
    std::fs::remove_file(&item).unwrap();
    let e = load_dataset(dir.path(), &|_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("00000/performance.json"), "{e}");
}

#[test]
fn inference_handles_short_and_rejects_bad_input() {
    let est = ArousalEstimator::pretrained().unwrap();
    for frames in [1usize, 5, 19, 20, 21, 75] {
        let mel = Array2::from_shape_fn((frames, 64), |(t, b)| -30.0 - (t + b) as f32 * 0.1);
        assert_eq!(est.predict(mel.view()).unwrap().len(), frames);
    }
    assert!(est.predict(Array2::<f32>::zeros((0, 64)).view()).is_err());
    let e = est
        .predict(Array2::<f32>::zeros((30, 128)).view())
        .unwrap_err()
        .to_string();
    assert!(e.contains("128 bands"), "{e}");
    let mut nan = Array2::<f32>::zeros((30, 64));
    nan[[7, 1]] = f32::NAN;
    assert!(est
        .predict(nan.view())
        .unwrap_err()
        .to_string()
        .contains("frame 7"));
}

#[test]
fn load_rejects_wrong_files_with_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let good = ArousalEstimator::pretrained().unwrap().to_bytes().unwrap();
    // Truncated.
    let p = dir.path().join("cut.safetensors");
    std::fs::write(&p, &good[..good.len() / 2]).unwrap();
    let e = ArousalEstimator::load(&p).unwrap_err().to_string();
    assert!(
        e.contains("cut.safetensors") && e.contains("truncated"),
        "{e}"
    );
    // Another network's weights.
    let bowing = bowing_net::BowChangeDetector::pretrained()
        .unwrap()
        .to_bytes()
        .unwrap();
    let e = ArousalEstimator::from_bytes(&bowing, Path::new("b.safetensors"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("bowing-net"), "{e}");
    // Missing file.
    assert!(ArousalEstimator::load(&dir.path().join("none.safetensors"))
        .unwrap_err()
        .to_string()
        .contains("none.safetensors"));
}

fn write_wav(path: &Path, seconds: f32, rate: u32) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    let n = (seconds * rate as f32) as usize;
    for i in 0..n {
        let t = i as f32 / rate as f32;
        let amp = 0.1 + 0.4 * (t / seconds);
        w.write_sample((amp * (2.0 * std::f32::consts::PI * 440.0 * t).sin() * 32767.0) as i16)
            .unwrap();
    }
    w.finalize().unwrap();
}

#[test]
fn deam_layout_loads_with_wav_audio() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join(DEAM_AROUSAL_CSV);
    std::fs::create_dir_all(csv.parent().unwrap()).unwrap();
    std::fs::create_dir_all(dir.path().join("MEMD_audio")).unwrap();
    let mut text = String::from(
        "song_id,sample_15000ms,sample_15500ms,sample_16000ms,sample_16500ms,sample_17000ms\n",
    );
    text.push_str("2,0.1,0.2,0.3,0.4,0.5\n");
    text.push_str("3,-0.1,-0.2,-0.3,,\n");
    text.push_str("5,0.0,NaN,0.1,0.1,0.1\n");
    std::fs::write(&csv, text).unwrap();
    for id in [2, 3, 5] {
        write_wav(
            &dir.path().join(format!("MEMD_audio/{id}.wav")),
            18.0,
            44_100,
        );
    }
    let rows = read_deam_arousal(&csv).unwrap();
    assert_eq!(rows.len(), 3);
    assert_eq!(rows[0].first_ms, 15_000);
    assert_eq!(rows[1].arousal, vec![-0.1, -0.2, -0.3]);
    assert_eq!(rows[2].arousal, vec![0.0]); // stops at NaN
    let data: ArousalSplits = load_deam(dir.path(), &|_, _| {}).unwrap();
    let all: Vec<&ArousalTrack> = data
        .train
        .iter()
        .chain(&data.val)
        .chain(&data.test)
        .collect();
    assert_eq!(all.len(), 3);
    let song2 = all.iter().find(|t| t.name == "2").unwrap();
    assert_eq!(song2.first_frame, 30); // 15 s at 2 Hz
    assert_eq!(song2.arousal.len(), 5);
    assert_eq!(song2.group, "deam");
    assert_eq!(song2.mel_db.ncols(), 64);
    assert!((35..=37).contains(&song2.mel_db.nrows()));
    // A song whose audio is missing is an error naming the file.
    std::fs::remove_file(dir.path().join("MEMD_audio/3.wav")).unwrap();
    let e = load_deam(dir.path(), &|_, _| {}).unwrap_err().to_string();
    assert!(e.contains("3.mp3"), "{e}");
    // A malformed header is an error naming the file and the cell.
    std::fs::write(&csv, "song_id,t15\n2,0.1\n").unwrap();
    let e = load_deam(dir.path(), &|_, _| {}).unwrap_err().to_string();
    assert!(e.contains("arousal.csv") && e.contains("t15"), "{e}");
    // Neither layout.
    let empty = tempfile::tempdir().unwrap();
    assert!(load_dataset(empty.path(), &|_, _| {})
        .unwrap_err()
        .to_string()
        .contains("DEAM"));
}
