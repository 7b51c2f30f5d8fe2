//! Method 1 on 180 s of rendered violin (a corpus étude, built-in synthesizer, 44.1 kHz):
//! the network alone on its mel frames (5 400 frames) — chunked as `Chunking::default()`
//! says (the default) and sequential — and the whole `generate` (resample + mel + network);
//! plus one training update (16 × 150 frames, forward + backward + Adam).
//!
//! `cargo bench -p violin-train --bench gru_infer`
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use candle_core::{DType, Device, Tensor};
use corpus::etude::EtudeConfig;
use corpus::item::{make_item, RendererKind};
use corpus::render::BowedStringSynth;
use criterion::{criterion_group, criterion_main, Criterion};
use gru_baseline::features::mel_frames;
use gru_baseline::{Config, GruBaseline, Loss};
use net_core::{Adam, AdamConfig};

fn audio_180s() -> dsp_mel::Audio {
    let etude = EtudeConfig {
        target_s: 185.0,
        ..EtudeConfig::default()
    };
    let item = make_item(
        8,
        &etude,
        &BowedStringSynth::default(),
        RendererKind::Builtin,
        false,
    )
    .unwrap();
    let audio = dsp_mel::Audio::new(item.audio, item.augmentation.sample_rate_hz).unwrap();
    let audio = dsp_mel::resample(&audio, 44_100).unwrap();
    let samples = audio.samples()[..44_100 * 180].to_vec();
    dsp_mel::Audio::new(samples, 44_100).unwrap()
}

fn bench(c: &mut Criterion) {
    let net = GruBaseline::pretrained().unwrap();
    let audio = audio_180s();
    let mel = mel_frames(&audio).unwrap();
    assert_eq!(mel.nrows(), 5401);
    let mut group = c.benchmark_group("gru-baseline");
    group.sample_size(10);
    group.bench_function("predict_mel_180s", |b| {
        b.iter(|| net.predict_mel(mel.view()).unwrap())
    });
    group.bench_function("predict_180s_sequential", |b| {
        b.iter(|| net.predict_normalized_exact(mel.view()).unwrap())
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
    let mut named: Vec<_> = vars
        .data()
        .lock()
        .unwrap()
        .iter()
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    named.sort_by(|a: &(String, _), b| a.0.cmp(&b.0));
    let mut adam = Adam::new(named, AdamConfig::default()).unwrap();
    let x = Tensor::from_vec(
        mel.iter()
            .take(16 * 150 * 128)
            .map(|v| (v + 40.0) / 20.0)
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
            adam.step_clipped(&l.backward().unwrap(), Some(1.0))
                .unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
