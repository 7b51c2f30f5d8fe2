//! Criterion benches of the mel/filter hot path on 180 s of 44.1 kHz audio.
//!
//! `cargo bench --bench dsp`
#![allow(clippy::expect_used, missing_docs)]

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use violin_skeleton::dsp_mel::filters::{filtfilt, median_filter, Butterworth, EdgeMode};
use violin_skeleton::dsp_mel::{resample, Audio, MelConfig, MelSpectrogram};

/// A deterministic violin-like test signal: harmonics of a slowly moving pitch plus noise.
fn test_signal(rate: u32, seconds: f32) -> Vec<f32> {
    let n = (rate as f32 * seconds) as usize;
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut phase = 0.0f32;
    (0..n)
        .map(|i| {
            let t = i as f32 / rate as f32;
            let f0 = 196.0 * (1.0 + 0.5 * (0.05 * t).sin());
            phase = (phase + f0 / rate as f32).fract();
            let tone: f32 = (1..8)
                .map(|h| (2.0 * std::f32::consts::PI * phase * h as f32).sin() / h as f32)
                .sum();
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let noise = (state >> 40) as f32 / (1u64 << 24) as f32 - 0.5;
            0.2 * tone + 0.01 * noise
        })
        .collect()
}

fn mel(c: &mut Criterion) {
    let samples = test_signal(44_100, 180.0);
    let mut group = c.benchmark_group("mel_180s_44k1");
    group.sample_size(20);
    for (name, cfg) in [
        ("mel30", MelConfig::bowing()),
        ("mel2", MelConfig::emotion()),
    ] {
        let plan = MelSpectrogram::new(cfg.at_sample_rate(44_100)).expect("valid config");
        group.bench_with_input(BenchmarkId::from_parameter(name), &samples, |b, s| {
            b.iter(|| plan.compute(s).expect("mel"))
        });
    }
    group.finish();
}

fn resampling(c: &mut Criterion) {
    let audio = Audio::new(test_signal(44_100, 180.0), 44_100).expect("audio");
    let mut group = c.benchmark_group("resample_180s");
    group.sample_size(10);
    group.bench_function("44k1_to_22k05", |b| {
        b.iter(|| resample(&audio, 22_050).expect("resample"))
    });
    group.finish();
}

fn filters(c: &mut Criterion) {
    let x: Vec<f64> = test_signal(30, 1e6 / 30.0)
        .into_iter()
        .map(f64::from)
        .collect();
    let tf = Butterworth::lowpass(4, 5.0, 30.0)
        .expect("design")
        .transfer_function();
    let mut group = c.benchmark_group("filters_1e6");
    group.sample_size(20);
    group.bench_function("filtfilt_butter4", |b| {
        b.iter(|| filtfilt(&tf.b, &tf.a, &x).expect("filtfilt"))
    });
    group.bench_function("median15_nearest", |b| {
        b.iter(|| median_filter(&x, 15, EdgeMode::Nearest).expect("median"))
    });
    group.finish();
}

criterion_group!(benches, mel, resampling, filters);
criterion_main!(benches);
