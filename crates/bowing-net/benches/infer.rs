//! Inference cost: frame probabilities (stride 1) over 180 s of mel frames (5 400 windows),
//! and one training step (8 sequences × 128 windows).
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use bowing_net::infer::frame_probabilities;
use bowing_net::nn::store;
use bowing_net::{BowChangeDetector, BowingNet, Config};
use candle_core::{DType, Device, Tensor};
use candle_nn::{VarBuilder, VarMap};
use criterion::{criterion_group, criterion_main, Criterion};
use ndarray::Array2;

fn mel_180s() -> Array2<f32> {
    Array2::from_shape_fn((5400, 128), |(t, b)| {
        -40.0 + 20.0 * ((t as f32 * 0.37).sin() * (b as f32 * 0.11).cos())
    })
}

fn bench(c: &mut Criterion) {
    let mel = mel_180s();
    let detector = BowChangeDetector::pretrained().unwrap();
    let mut group = c.benchmark_group("bowing-net");
    group.sample_size(10);
    group.bench_function("frame_probabilities_180s", |b| {
        b.iter(|| frame_probabilities(detector.net(), mel.view()).unwrap())
    });
    group.bench_function("detect_frames_180s", |b| {
        b.iter(|| detector.detect_frames(mel.view()).unwrap())
    });

    let varmap = VarMap::new();
    let net = BowingNet::new(
        &Config::default(),
        VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu),
    )
    .unwrap();
    store::init_seeded(&varmap, 1, |n, d| {
        (!n.starts_with("norm."))
            .then(|| (6.0 / d.iter().skip(1).product::<usize>().max(1) as f64).sqrt())
    })
    .unwrap();
    let seq = bowing_net::infer::sequence_frames(&net, 128);
    let x = Tensor::from_vec(
        mel.slice(ndarray::s![..seq, ..])
            .iter()
            .cycle()
            .take(8 * seq * 128)
            .copied()
            .collect::<Vec<f32>>(),
        (8, seq, 128),
        &Device::Cpu,
    )
    .unwrap();
    group.bench_function("train_step_8x128_windows", |b| {
        b.iter(|| {
            let l = net.sequence_logits(&x, true).unwrap();
            let loss = l.sqr().unwrap().mean_all().unwrap();
            loss.backward().unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
