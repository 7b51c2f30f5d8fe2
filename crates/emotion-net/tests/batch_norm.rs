#![allow(clippy::unwrap_used, clippy::expect_used)]
//! Re-estimating the batch-norm statistics without dropout.

mod common;

use emotion_net::Config;
use net_core::gradcheck::uniform_tensor;

#[test]
fn recalibrated_inference_matches_batch_statistics_on_the_calibration_batch() {
    let cfg = Config {
        conv_dropout: 0.0,
        dense_dropout: 0.0,
        gru_dropout: 0.0,
        ..Config::default()
    };
    let (_, net) = common::seeded_net(
        &cfg,
        5,
        &common::Keep {
            containing: &["gamma"],
            zero_biases: false,
        },
    );
    let x = uniform_tensor(&[4, 20, 64], 6, 3.0)
        .unwrap()
        .affine(1.0, 2.0)
        .unwrap();
    let before = net.forward_t(&x, false).unwrap().to_vec2::<f32>().unwrap();
    net.recalibrate_batch_norm(&[]).unwrap(); // no batches: nothing changes
    assert_eq!(
        net.forward_t(&x, false).unwrap().to_vec2::<f32>().unwrap(),
        before
    );
    net.recalibrate_batch_norm(std::slice::from_ref(&x))
        .unwrap();
    let after = net.forward_t(&x, false).unwrap().to_vec2::<f32>().unwrap();
    // With dropout off a training pass normalises with the batch's statistics: the same
    // numbers the recalibration stored.
    let batch = net.forward_t(&x, true).unwrap().to_vec2::<f32>().unwrap();
    let mut moved = false;
    for ((a, b), c) in after
        .iter()
        .flatten()
        .zip(batch.iter().flatten())
        .zip(before.iter().flatten())
    {
        assert!((a - b).abs() < 1e-3, "{a} vs {b}");
        moved |= (a - c).abs() > 1e-3;
    }
    assert!(moved, "the statistics did not change");
    let stats = net.running_stats();
    assert_eq!(stats.len(), 6);
}
