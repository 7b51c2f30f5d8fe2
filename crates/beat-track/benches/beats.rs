//! Onset strength, tempo, beats and downbeats on 180 s of synthetic violin at 22 050 Hz.
//!
//! `cargo bench -p beat-track --bench beats`
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use beat_track::synth::{render, SynthConfig};
use beat_track::{BeatConfig, BeatTracker, OnsetConfig, OnsetStrength};
use criterion::{criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    let piece = render(&SynthConfig {
        seed: 3,
        tempo_bpm: 100.0,
        bars: 75,
        ..SynthConfig::default()
    })
    .expect("synth renders");
    let samples = &piece.samples[..(180 * 22_050).min(piece.samples.len())];
    let mut group = c.benchmark_group("beats_180s");
    group.sample_size(20);
    let tracker = BeatTracker::new(BeatConfig::default()).expect("valid config");
    group.bench_function("beat_track_full", |b| {
        b.iter(|| tracker.track(samples, None).expect("tracks"))
    });
    let onset = OnsetStrength::new(OnsetConfig::default()).expect("valid config");
    group.bench_function("onset_strength", |b| {
        b.iter(|| onset.compute(samples).expect("onsets"))
    });
    let env = onset.compute(samples).expect("onsets");
    group.bench_function("tempo", |b| {
        b.iter(|| beat_track::estimate_tempo(&env.median, 22_050, 512, &Default::default()))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
