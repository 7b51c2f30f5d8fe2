//! The shipped weights: they load, round-trip through a file, ignore the recording's level,
//! stay low on silence and refuse malformed input and other files.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use beat_net::BeatActivation;
use ndarray::Array2;

/// A clicking note every 15 frames (120 bpm), louder every fourth.
fn clicks(level_db: f32) -> Array2<f32> {
    Array2::from_shape_fn((600, 128), |(t, b)| {
        let phase = (t % 15) as f32;
        let accent = if (t / 15) % 4 == 0 { 6.0 } else { 0.0 };
        level_db + accent - phase * 3.0 - (b as f32 - 30.0).abs() * 0.4
    })
}

#[test]
fn level_does_not_matter_and_clicks_beat_silence() {
    let net = BeatActivation::pretrained().unwrap();
    let loud = net.activations(clicks(-10.0).view()).unwrap();
    let quiet = net.activations(clicks(-29.0).view()).unwrap();
    assert_eq!(loud.len(), 600);
    let diff = loud
        .any_beat()
        .iter()
        .zip(quiet.any_beat())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    assert!(diff < 0.02, "{diff}");
    let silence = net
        .activations(Array2::from_elem((600, 128), -100.0f32).view())
        .unwrap();
    let peak = |v: Vec<f32>| v.into_iter().fold(0.0f32, f32::max);
    let silent_peak = peak(silence.any_beat());
    assert!(silent_peak < 0.2, "{silent_peak}");
    assert!(peak(loud.any_beat()) > silent_peak);
    assert!(net
        .activations(Array2::<f32>::zeros((0, 128)).view())
        .unwrap()
        .is_empty());
    assert!(net
        .activations(Array2::<f32>::zeros((10, 64)).view())
        .is_err());
}

#[test]
fn weights_round_trip_and_other_files_are_refused() {
    let net = BeatActivation::pretrained().unwrap();
    assert!(net.training_info().contains("epoch"));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("w.safetensors");
    net.save(&path).unwrap();
    let again = BeatActivation::load(&path).unwrap();
    let mel = clicks(-20.0);
    assert_eq!(
        net.activations(mel.view()).unwrap(),
        again.activations(mel.view()).unwrap()
    );
    let bytes = std::fs::read(&path).unwrap();
    assert!(BeatActivation::from_bytes(&bytes[..bytes.len() / 2], Path::new("half")).is_err());
    assert!(BeatActivation::from_bytes(b"not weights", Path::new("junk")).is_err());
}

/// The inference path (ndarray products) gives the activations the candle graph gives.
#[test]
fn inference_path_equals_the_training_graph() {
    let net = BeatActivation::pretrained().unwrap();
    let mel = clicks(-12.0);
    let fast = net.activations(mel.view()).unwrap();
    let x = beat_net::features::frame_features(mel.view()).unwrap();
    let (frames, f) = x.dim();
    let input = candle_core::Tensor::from_vec(
        x.iter().copied().collect::<Vec<f32>>(),
        (1, frames, f),
        &candle_core::Device::Cpu,
    )
    .unwrap();
    let graph =
        beat_net::activation::probabilities(&net.net().forward_t(&input, false).unwrap()).unwrap();
    for (a, b) in fast
        .beat
        .iter()
        .chain(&fast.downbeat)
        .zip(graph.beat.iter().chain(&graph.downbeat))
    {
        assert!((a - b).abs() < 1e-5, "{a} vs {b}");
    }
}
