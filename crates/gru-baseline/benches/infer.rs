//! Method 1 inference on 180 s: the network alone on precomputed mel frames (5 400 frames,
//! one stream, state carried across 30 s chunks), and the whole `generate` from 44.1 kHz
//! audio (resample + mel + network); plus one training update (16 × 150 frames).
//!
//! `cargo bench -p gru-baseline --bench infer`
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use candle_core::{DType, Device, Tensor};
use criterion::{criterion_group, criterion_main, Criterion};
use gru_baseline::train::Adam;
use gru_baseline::{Config, GruBaseline, Loss};
use ndarray::Array2;

fn mel_180s() -> Array2<f32> {
    Array2::from_shape_fn((5400, 128), |(t, b)| {
        -40.0 + 20.0 * ((t as f32 * 0.37).sin() * (b as f32 * 0.11).cos())
    })
}

fn audio_180s() -> dsp_mel::Audio {
    let rate = 44_100u32;
    let mut phase = 0f32;
    let samples = (0..rate as usize * 180)
        .map(|i| {
            let t = i as f32 / rate as f32;
            phase = (phase + 196.0 * (1.0 + 0.5 * (0.05 * t).sin()) / rate as f32).fract();
            (1..6)
                .map(|h| (std::f32::consts::TAU * phase * h as f32).sin() / h as f32)
                .sum::<f32>()
                * 0.2
        })
        .collect();
    dsp_mel::Audio::new(samples, rate).unwrap()
}

fn bench(c: &mut Criterion) {
    let net = GruBaseline::pretrained().unwrap();
    let mel = mel_180s();
    let audio = audio_180s();
    let mut group = c.benchmark_group("gru-baseline");
    group.sample_size(10);
    group.bench_function("predict_mel_180s", |b| {
        b.iter(|| net.predict_mel(mel.view()).unwrap())
    });
    group.bench_function("generate_180s_audio_44k", |b| {
        b.iter(|| net.generate(&audio).unwrap())
    });

    let cfg = Config::default();
    let vars = GruBaseline::init_vars(&cfg, 1).unwrap();
    let train_net = GruBaseline::new(
        &cfg,
        candle_nn::VarBuilder::from_varmap(&vars, DType::F32, &Device::Cpu),
    )
    .unwrap();
    let named = vars
        .data()
        .lock()
        .unwrap()
        .iter()
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    let mut adam = Adam::new(named, 1e-3).unwrap();
    let x = Tensor::from_vec(
        mel.iter()
            .take(16 * 150 * 128)
            .copied()
            .collect::<Vec<f32>>(),
        (16, 150, 128),
        &Device::Cpu,
    )
    .unwrap();
    let y = Tensor::zeros((16, 150, 20), DType::F32, &Device::Cpu).unwrap();
    let loss = Loss::default();
    group.bench_function("train_update_16x150", |b| {
        b.iter(|| {
            let pred = train_net.forward_t(&x, true).unwrap();
            let l = loss.compute(&pred, &y, None).unwrap();
            adam.step(&l.backward().unwrap(), Some(1.0)).unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
