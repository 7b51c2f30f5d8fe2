//! The phase-tree evaluation over a whole spectrogram equals the per-window network.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use bowing_net::infer::{
    frame_probabilities, frame_probabilities_per_window, tile_windows, TILE_WINDOWS,
};
use bowing_net::model::WeightInit;
use bowing_net::{BowingNet, Config};
use candle_nn::VarMap;
use ndarray::Array2;
use net_core::rng::Rng;

fn random_net(seed: u64) -> (VarMap, BowingNet) {
    BowingNet::seeded(&Config::default(), WeightInit::HeUniform, seed).unwrap()
}

fn random_mel(frames: usize, seed: u64) -> Array2<f32> {
    let mut rng = Rng::new(seed);
    Array2::from_shape_fn((frames, 128), |(t, b)| {
        -40.0 + 10.0 * ((t as f32 * 0.3 + b as f32 * 0.1).sin()) + rng.uniform(-5.0, 5.0) as f32
    })
}

#[test]
fn phase_tree_equals_per_window_forward() {
    let (_vm, net) = random_net(11);
    // Longer than one tile, with a ragged end, so tile borders and every phase are covered.
    let frames = TILE_WINDOWS + 77;
    let mel = random_mel(frames, 5);
    let fast = frame_probabilities(&net, mel.view()).unwrap();
    assert_eq!(fast.len(), frames);
    let spread = fast.iter().cloned().fold(f32::NEG_INFINITY, f32::max)
        - fast.iter().cloned().fold(f32::INFINITY, f32::min);
    assert!(spread > 1e-3, "a random network should not be constant");
    // Two tiles of equal size: the start, both sides of the tile border, and the end;
    // every pool phase occurs.
    let border = tile_windows(frames);
    assert!(border < frames && 2 * border >= frames);
    for range in [0..80, border - 40..border + 40, frames - 40..frames] {
        let slow = frame_probabilities_per_window(&net, mel.view(), range.clone()).unwrap();
        for (t, b) in range.zip(&slow) {
            let a = fast[t];
            assert!((a - b).abs() < 1e-4, "frame {t}: tree {a}, per window {b}");
        }
    }
}

#[test]
fn short_recordings_are_padded_with_silence() {
    let (_vm, net) = random_net(12);
    for frames in [1usize, 7, 59, 61] {
        let mel = random_mel(frames, frames as u64);
        let fast = frame_probabilities(&net, mel.view()).unwrap();
        let slow = frame_probabilities_per_window(&net, mel.view(), 0..frames).unwrap();
        assert_eq!(fast.len(), frames);
        for (a, b) in fast.iter().zip(&slow) {
            assert!((a - b).abs() < 1e-4);
        }
    }
}

#[test]
fn bad_inputs_are_typed_errors() {
    let (_vm, net) = random_net(13);
    let empty = Array2::<f32>::zeros((0, 128));
    assert!(frame_probabilities(&net, empty.view()).is_err());
    let narrow = Array2::<f32>::zeros((100, 64));
    let e = frame_probabilities(&net, narrow.view())
        .unwrap_err()
        .to_string();
    assert!(e.contains("64 bands"), "{e}");
    let mut nan = random_mel(100, 1);
    nan[[50, 3]] = f32::NAN;
    let e = frame_probabilities(&net, nan.view())
        .unwrap_err()
        .to_string();
    assert!(e.contains("frame 50"), "{e}");
}
