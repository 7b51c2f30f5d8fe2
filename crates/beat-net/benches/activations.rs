//! The shipped network's activations for 180 s (5 400 frames) of a synthetic mel
//! spectrogram, and those activations decoded by the bar-pointer decoder: the learned beat
//! path of the analysis (issue 20's budget: ≤ 100 ms on one core).
//!
//! `RAYON_NUM_THREADS=1 CANDLE_NUM_THREADS=1 cargo bench -p beat-net --bench activations`
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use beat_net::BeatActivation;
use criterion::{criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    let net = BeatActivation::pretrained().expect("weights");
    // A note every half second: loud attack, decaying over the beat.
    let mel = ndarray::Array2::from_shape_fn((5400, 128), |(t, b)| {
        let phase = (t % 15) as f32;
        -20.0 - phase * 2.0 - (b as f32 - 40.0).abs() * 0.3
    });
    let act = net.activations(mel.view()).expect("runs");
    let cfg = beat_track::bar_pointer::BarPointerConfig::default();
    let mut group = c.benchmark_group("beat_net_180s");
    group.sample_size(10);
    group.bench_function("activations", |b| {
        b.iter(|| net.activations(mel.view()).expect("runs"))
    });
    group.bench_function("activations_and_bar_pointer", |b| {
        b.iter(|| {
            let act = net.activations(mel.view()).expect("runs");
            beat_track::bar_pointer::decode(&act.beat, &act.downbeat, &cfg).expect("decodes")
        })
    });
    group.bench_function("bar_pointer_on_these_activations", |b| {
        b.iter(|| beat_track::bar_pointer::decode(&act.beat, &act.downbeat, &cfg).expect("decodes"))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
