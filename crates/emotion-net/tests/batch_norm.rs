#![allow(clippy::unwrap_used, clippy::expect_used)]
//! Re-estimating the batch-norm statistics without dropout.

use candle_core::{DType, Device};
use candle_nn::{VarBuilder, VarMap};
use emotion_net::{Config, EmotionNet};
use net_store::gradcheck::uniform_tensor;
use net_store::vars;

#[test]
fn recalibrated_inference_matches_batch_statistics_on_the_calibration_batch() {
    let cfg = Config {
        conv_dropout: 0.0,
        dense_dropout: 0.0,
        gru_dropout: 0.0,
        ..Config::default()
    };
    let varmap = VarMap::new();
    let net = EmotionNet::new(
        &cfg,
        VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu),
    )
    .unwrap();
    vars::init_seeded(&varmap, 5, |n, d| {
        if n.starts_with("norm.") || n.contains("running_") || n.contains("gamma") {
            None
        } else {
            Some((3.0 / d.iter().skip(1).product::<usize>().max(1) as f64).sqrt())
        }
    })
    .unwrap();
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
