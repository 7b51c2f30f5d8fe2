//! Onset strength, tempo, beats, metre and downbeats on 180 s of synthetic violin (a corpus
//! étude at 100 bpm, the corpus's bowed-string synthesizer) at 22 050 Hz,
//! stage by stage and as one `BeatTracker::track` call (without and with notes).
//!
//! `cargo bench -p beat-track --bench beats`
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use beat_track::{
    estimate_meter, estimate_tempo, track_beats, BarEvidence, BeatConfig, BeatTracker, OnsetConfig,
    OnsetStrength,
};
use corpus::item::clean_etude;
use criterion::{criterion_group, criterion_main, Criterion};
use pitch_track::{segment_notes, NoteConfig, PitchConfig, PitchTracker};

fn bench(c: &mut Criterion) {
    let item = clean_etude(3, 180.0, (100.0, 100.0)).expect("corpus item renders");
    let samples = &item.audio[..(180 * 22_050).min(item.audio.len())];
    let cfg = BeatConfig::default();
    let tracker = BeatTracker::new(cfg.clone()).expect("valid config");
    let track = PitchTracker::new(PitchConfig::default())
        .expect("valid config")
        .track(samples)
        .expect("tracks");
    let notes = segment_notes(&track, samples, 22_050, &NoteConfig::default()).expect("notes");
    let onset = OnsetStrength::new(OnsetConfig::default()).expect("valid config");
    let env = onset.compute(samples).expect("onsets");
    let bpm = estimate_tempo(&env.mean, 22_050, 512, &cfg.tempo).expect("a tempo");
    let frame_rate = 22_050.0 / 512.0;
    let beats_s: Vec<f64> = track_beats(&env.mean, bpm, frame_rate, cfg.tightness, cfg.trim)
        .into_iter()
        .map(|f| f as f64 * env.hop_s)
        .collect();

    let mut group = c.benchmark_group("beats_180s");
    group.sample_size(20);
    group.bench_function("beat_track_full", |b| {
        b.iter(|| tracker.track(samples, None).expect("tracks"))
    });
    group.bench_function("beat_track_full_with_notes", |b| {
        b.iter(|| tracker.track(samples, Some(&notes)).expect("tracks"))
    });
    group.bench_function("onset_strength", |b| {
        b.iter(|| onset.compute(samples).expect("onsets"))
    });
    group.bench_function("tempo", |b| {
        b.iter(|| estimate_tempo(&env.mean, 22_050, 512, &cfg.tempo))
    });
    group.bench_function("dp_beats", |b| {
        b.iter(|| track_beats(&env.mean, bpm, frame_rate, cfg.tightness, cfg.trim))
    });
    group.bench_function("meter_with_notes", |b| {
        b.iter(|| {
            estimate_meter(
                &beats_s,
                &env,
                BarEvidence::notes(Some(&notes)),
                bpm,
                &cfg.meter,
            )
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
