//! Inference cost: the CNN's frame probabilities (stride 1) over 180 s of mel frames (5 400
//! windows), the stroke network's and the default ensemble's whole analysis of the same
//! 180 s, and one CNN training step of the default settings. With
//! `BOWING_BENCH_ENSEMBLE_CNN=FILE`, also the ensemble with that file's CNN.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use bowing_net::infer::frame_probabilities;
use bowing_net::{BowChangeDetector, BowingNet, Config};
use candle_core::{Device, Tensor};
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
    // The stroke network (default): bow changes, directions and strings, decoded.
    let strokes = bowing_net::BowingModel::pretrained_strokes().unwrap();
    group.bench_function("stroke_net_analyze_180s", |b| {
        b.iter(|| strokes.analyze_mel(mel.view()).unwrap())
    });

    // The shipped default: the CNN and the stroke network averaged, decoded.
    let ensemble = bowing_net::BowingModel::pretrained().unwrap();
    group.bench_function("default_ensemble_analyze_180s", |b| {
        b.iter(|| ensemble.analyze_mel(mel.view()).unwrap())
    });
    // A candidate CNN for the ensemble (`train bowing` weights), timed beside the shipped one
    // when `BOWING_BENCH_ENSEMBLE_CNN` names its file.
    if let Some(path) = std::env::var_os("BOWING_BENCH_ENSEMBLE_CNN") {
        let candidate =
            bowing_net::BowingModel::ensemble_from_files(Some(path.as_ref()), None).unwrap();
        group.bench_function("candidate_cnn_ensemble_analyze_180s", |b| {
            b.iter(|| candidate.analyze_mel(mel.view()).unwrap())
        });
    }

    // One training step of the default settings: forward through the phase tree in
    // training mode (dropout on) and backward.
    let cfg = bowing_net::TrainConfig::default();
    let (_varmap, net) = BowingNet::seeded(&Config::default(), cfg.init, 1).unwrap();
    let (b, w) = (cfg.batch_sequences, cfg.sequence_windows);
    let seq = bowing_net::infer::sequence_frames(&net, w);
    let x = Tensor::from_vec(
        mel.slice(ndarray::s![..seq, ..])
            .iter()
            .cycle()
            .take(b * seq * 128)
            .copied()
            .collect::<Vec<f32>>(),
        (b, seq, 128),
        &Device::Cpu,
    )
    .unwrap();
    group.bench_function(format!("train_step_{b}x{w}_windows"), |bench| {
        bench.iter(|| {
            let l = net.sequence_logits(&x, true).unwrap();
            let loss = l.sqr().unwrap().mean_all().unwrap();
            loss.backward().unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
