//! Inference cost: arousal of 180 s of 2 fps mel frames (360 frames, 35 windows of 20 frames every 10).
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use emotion_net::ArousalEstimator;
use ndarray::Array2;

fn bench(c: &mut Criterion) {
    let mel = Array2::from_shape_fn((360, 64), |(t, b)| {
        -40.0 + 20.0 * ((t as f32 * 0.37).sin() * (b as f32 * 0.11).cos())
    });
    let est = ArousalEstimator::pretrained().unwrap();
    let mut group = c.benchmark_group("emotion-net");
    group.sample_size(20);
    group.bench_function("predict_180s", |b| {
        b.iter(|| est.predict(mel.view()).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
