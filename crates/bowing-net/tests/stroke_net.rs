//! The stroke network on bad and degenerate input, and its weights file checks.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use std::path::Path;

use bowing_net::stroke::{stroke_input, StrokeDetector};
use bowing_net::BowingModel;
use ndarray::Array2;

fn detector() -> StrokeDetector {
    BowingModel::pretrained_strokes().unwrap()
}

fn audio(samples: Vec<f32>) -> dsp_mel::Audio {
    dsp_mel::Audio::new(samples, 22_050).unwrap()
}

#[test]
fn silence_and_noise_give_nothing_played_and_no_changes() {
    let mut rng = net_core::rng::Rng::new(5);
    let noise: Vec<f32> = (0..22_050 * 4).map(|_| 0.1 * rng.normal() as f32).collect();
    for samples in [vec![0.0; 22_050 * 5], noise] {
        let a = detector().analyze_audio(&audio(samples.clone())).unwrap();
        assert!(a.played_s.is_empty(), "{:?}", a.played_s);
        assert!(a.bow_changes_s.is_empty(), "{:?}", a.bow_changes_s);
        let b = BowingModel::pretrained()
            .unwrap()
            .analyze_audio(&audio(samples))
            .unwrap();
        assert!(b.bow_changes_s.is_empty(), "{:?}", b.bow_changes_s);
    }
}

#[test]
fn one_second_clipping_and_a_few_samples_give_a_result_without_panicking() {
    let one_s: Vec<f32> = (0..22_050)
        .map(|i| 0.3 * (i as f32 * 440.0 * std::f32::consts::TAU / 22_050.0).sin())
        .collect();
    let a = detector().analyze_audio(&audio(one_s.clone())).unwrap();
    assert_eq!(a.played_s.len(), 1, "{:?}", a.played_s);
    assert!(a.bow_changes_s.len() <= 3);
    let clipped: Vec<f32> = one_s.iter().map(|v| (v * 20.0).clamp(-1.0, 1.0)).collect();
    detector().analyze_audio(&audio(clipped)).unwrap();
    // Too short for one frame.
    let a = detector().analyze_audio(&audio(vec![0.1; 10])).unwrap();
    assert!(a.played_s.is_empty() && a.bow_changes_s.is_empty());
}

#[test]
fn gain_does_not_change_the_result() {
    // A bowed tone with four changes of level, at −1 dBFS and −20 dBFS.
    let sr = 22_050usize;
    let tone: Vec<f32> = (0..sr * 6)
        .map(|i| {
            let t = i as f32 / sr as f32;
            let env = 0.5 + 0.5 * (t * std::f32::consts::PI * 1.5).sin().abs();
            env * (t * 392.0 * std::f32::consts::TAU).sin()
        })
        .collect();
    let peak = tone.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    let at = |db: f32| -> Vec<f32> {
        let g = 10f32.powf(db / 20.0) / peak;
        tone.iter().map(|v| v * g).collect()
    };
    let loud = detector().analyze_audio(&audio(at(-1.0))).unwrap();
    let quiet = detector().analyze_audio(&audio(at(-20.0))).unwrap();
    assert_eq!(loud.bow_changes_s.len(), quiet.bow_changes_s.len());
    for (a, b) in loud.bow_changes_s.iter().zip(&quiet.bow_changes_s) {
        assert!((a - b).abs() < 0.04, "{a} vs {b}");
    }
    assert_eq!(loud.played_s.len(), quiet.played_s.len());
    assert_eq!(loud.frames.string.len(), quiet.frames.string.len());
}

#[test]
fn nan_and_wrongly_shaped_spectrograms_are_refused() {
    let d = detector();
    let mut mel = Array2::from_elem((100, 128), -40.0f32);
    mel[(10, 3)] = f32::NAN;
    let e = d.analyze_mel(mel.view()).unwrap_err().to_string();
    assert!(e.contains("NaN") || e.contains("finite"), "{e}");
    let e = d
        .analyze_mel(Array2::from_elem((100, 64), -40.0f32).view())
        .unwrap_err()
        .to_string();
    assert!(e.contains("128") || e.contains("64"), "{e}");
    assert_eq!(
        stroke_input(Array2::<f32>::zeros((0, 128)).view()).nrows(),
        0
    );
}

#[test]
fn weights_of_the_wrong_shape_or_kind_are_refused_with_names() {
    let d = detector();
    let bytes = d.to_bytes().unwrap();
    // Round trip: the same tensors and metadata.
    let back = StrokeDetector::from_bytes(&bytes, Path::new("w.safetensors")).unwrap();
    let (a, b) = (
        net_core::file::decode(&bytes, Path::new("a")).unwrap(),
        net_core::file::decode(&back.to_bytes().unwrap(), Path::new("b")).unwrap(),
    );
    assert_eq!(a.metadata, b.metadata);
    for (name, t) in &a.tensors {
        let diff = (t - &b.tensors[name])
            .unwrap()
            .abs()
            .unwrap()
            .sum_all()
            .unwrap();
        assert_eq!(diff.to_scalar::<f32>().unwrap(), 0.0, "{name}");
    }
    // A tensor of the wrong shape: rebuild with a narrower trunk but keep the config.
    let file = net_core::file::decode(&bytes, Path::new("w")).unwrap();
    let mut tensors: Vec<(String, candle_core::Tensor)> = file.tensors.into_iter().collect();
    tensors.sort_by(|a, b| a.0.cmp(&b.0));
    let name = "heads.weight";
    let (_, t) = tensors.iter_mut().find(|(n, _)| n == name).unwrap();
    *t = candle_core::Tensor::zeros((6, 3), candle_core::DType::F32, &candle_core::Device::Cpu)
        .unwrap();
    let bad = net_core::file::encode(&tensors, file.metadata).unwrap();
    let e = StrokeDetector::from_bytes(&bad, Path::new("bad.safetensors"))
        .unwrap_err()
        .to_string();
    assert!(e.contains(name) && e.contains("bad.safetensors"), "{e}");
    // The CNN's file is a bowing model too, told apart by its format.
    let dir = tempfile::tempdir().unwrap();
    let cnn = dir.path().join("cnn.safetensors");
    bowing_net::BowChangeDetector::pretrained()
        .unwrap()
        .save(&cnn)
        .unwrap();
    assert!(matches!(
        BowingModel::load(&cnn).unwrap(),
        BowingModel::Cnn(_)
    ));
    let strokes = dir.path().join("s.safetensors");
    d.save(&strokes).unwrap();
    assert!(matches!(
        BowingModel::load(&strokes).unwrap(),
        BowingModel::Strokes(_)
    ));
    std::fs::write(&strokes, &bytes[..bytes.len() / 2]).unwrap();
    let e = BowingModel::load(&strokes).unwrap_err().to_string();
    assert!(e.contains("s.safetensors"), "{e}");
}

#[test]
fn the_direction_decoder_travels_with_the_weights_and_uses_the_down_output() {
    use bowing_net::stroke::direction::DirectionDecoder;
    use performance::BowDirection::{Down, Up};
    use performance::Note;
    let mut d = detector();
    let decoder = DirectionDecoder {
        net_weight: 2.0,
        rule_weight: 0.25,
        stay_probability: 0.1,
        downbeat_weight: 1.0,
        beat_weight: 0.5,
        long_runs: Some(bowing_net::stroke::direction::LongRunStay {
            min_frames: 6,
            threshold: 0.65,
            stay_probability: 0.2,
        }),
        choice: bowing_net::stroke::direction::DirectionChoice::MostProbablePerStroke,
    };
    d.set_direction_decoder(Some(decoder));
    let back = StrokeDetector::from_bytes(&d.to_bytes().unwrap(), Path::new("w")).unwrap();
    assert_eq!(back.direction_decoder(), Some(decoder));
    // A file whose direction decoder is nonsense is refused, naming the field.
    let mut bad = detector();
    bad.set_direction_decoder(Some(DirectionDecoder {
        stay_probability: 1.5,
        ..decoder
    }));
    let err = StrokeDetector::from_bytes(&bad.to_bytes().unwrap(), Path::new("w.safetensors"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("stay_probability") && err.contains("w.safetensors"),
        "{err}"
    );
    let mut bad_long = detector();
    bad_long.set_direction_decoder(Some(DirectionDecoder {
        long_runs: Some(bowing_net::stroke::direction::LongRunStay {
            min_frames: 6,
            threshold: 0.65,
            stay_probability: 1.5,
        }),
        ..decoder
    }));
    let err = StrokeDetector::from_bytes(&bad_long.to_bytes().unwrap(), Path::new("w"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("long_runs.stay_probability"), "{err}");
    // Two one-second strokes; the network hears the first as an up-bow, the second as a
    // down-bow, against the rules' down-up.
    let notes = [Note::new(0.0, 1.0, 67), Note::new(1.0, 2.0, 69)];
    let mut found = back
        .analyze_mel(Array2::from_elem((60, 128), -100.0f32).view())
        .unwrap();
    found.frames.down = [vec![0.05f32; 30], vec![0.95f32; 30]].concat();
    assert_eq!(
        found.directions(&[0.0, 1.0], &notes, &[], &[]),
        vec![Up, Down]
    );
    // Without a decoder, or without the down output (no beats either), the rules decide.
    found.direction_decoder = None;
    assert_eq!(
        found.directions(&[0.0, 1.0], &notes, &[], &[]),
        vec![Down, Up]
    );
    found.direction_decoder = Some(decoder);
    found.frames.down.clear();
    assert_eq!(
        found.directions(&[0.0, 1.0], &notes, &[], &[]),
        vec![Down, Up]
    );
}

#[test]
fn a_stroke_file_joins_the_cnn_as_the_shipped_one_does() {
    let dir = tempfile::tempdir().unwrap();
    let strokes = dir.path().join("s.safetensors");
    detector().save(&strokes).unwrap();
    // The shipped file, read back, averaged with the CNN: the shipped ensemble exactly.
    let mel = Array2::from_shape_fn((200, 128), |(t, b)| {
        -60.0 + 30.0 * (((t / 7) as f32 + b as f32 * 0.37).sin())
    });
    let shipped = BowingModel::pretrained().unwrap();
    let given = BowingModel::ensemble_with_strokes_file(&strokes).unwrap();
    assert!(matches!(given, BowingModel::Ensemble(..)));
    let (a, b) = (
        shipped.analyze_mel(mel.view()).unwrap(),
        given.analyze_mel(mel.view()).unwrap(),
    );
    assert_eq!(a.bow_changes_s, b.bow_changes_s);
    assert_eq!(a.frames.change, b.frames.change);
    // Without an ensemble decoder it cannot be averaged: refused, naming the file.
    let mut bare = detector();
    bare.set_ensemble_decoder(None);
    let no_decoder = dir.path().join("bare.safetensors");
    bare.save(&no_decoder).unwrap();
    let e = BowingModel::ensemble_with_strokes_file(&no_decoder)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bare.safetensors") && e.contains("ensemble decoder"),
        "{e}"
    );
    assert!(BowingModel::strokes_file(&no_decoder).is_ok());
    // A CNN file is not a stroke network.
    let cnn = dir.path().join("cnn.safetensors");
    bowing_net::BowChangeDetector::pretrained()
        .unwrap()
        .save(&cnn)
        .unwrap();
    let e = BowingModel::strokes_file(&cnn).unwrap_err().to_string();
    assert!(e.contains("cnn.safetensors") && e.contains("CNN"), "{e}");
}

#[test]
fn a_cnn_file_joins_the_stroke_network_as_the_shipped_one_does() {
    let dir = tempfile::tempdir().unwrap();
    let mel = Array2::from_shape_fn((200, 128), |(t, b)| {
        -60.0 + 30.0 * (((t / 5) as f32 + b as f32 * 0.21).cos())
    });
    let changes = |m: &BowingModel| m.analyze_mel(mel.view()).unwrap().frames.change;
    // The shipped ensemble CNN, written out and read back: the shipped ensemble exactly.
    let shipped_cnn = dir.path().join("ensemble-cnn.safetensors");
    BowingModel::pretrained_ensemble_cnn()
        .unwrap()
        .save(&shipped_cnn)
        .unwrap();
    let shipped = changes(&BowingModel::pretrained().unwrap());
    let given = BowingModel::ensemble_from_files(Some(&shipped_cnn), None).unwrap();
    assert_eq!(changes(&given), shipped);
    // Another CNN (the one trained on études) changes the averaged probabilities.
    let etude_cnn = dir.path().join("etude-cnn.safetensors");
    bowing_net::BowChangeDetector::pretrained()
        .unwrap()
        .save(&etude_cnn)
        .unwrap();
    let other = BowingModel::ensemble_from_files(Some(&etude_cnn), None).unwrap();
    assert_ne!(changes(&other), shipped);
    // A stroke-network file is not a CNN: refused, naming the file.
    let strokes = dir.path().join("s.safetensors");
    detector().save(&strokes).unwrap();
    let e = BowingModel::ensemble_from_files(Some(&strokes), None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("s.safetensors") && e.contains("not the bow-change CNN"),
        "{e}"
    );
    // Both halves from files.
    let both = BowingModel::ensemble_from_files(Some(&shipped_cnn), Some(&strokes)).unwrap();
    assert_eq!(
        changes(&both),
        changes(&BowingModel::ensemble_with_strokes_file(&strokes).unwrap())
    );
}
