//! pYIN and note segmentation on 180 s of synthetic violin at 22 050 Hz, hop 256.
//!
//! `cargo bench -p pitch-track --bench pitch`
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use pitch_track::synth::{render, SynthConfig};
use pitch_track::{segment_notes, NoteConfig, PitchConfig, PitchTracker};

fn bench(c: &mut Criterion) {
    let piece = render(&SynthConfig {
        seed: 3,
        tempo_bpm: 100.0,
        bars: 75, // 75 bars of 4/4 at 100 bpm = 180 s
        ..SynthConfig::default()
    })
    .expect("synth renders");
    let samples = &piece.samples[..(180 * 22_050).min(piece.samples.len())];
    let mut group = c.benchmark_group("pitch_180s");
    group.sample_size(10);
    for resolution in [0.2, 0.1] {
        let tracker = PitchTracker::new(PitchConfig {
            resolution_semitones: resolution,
            ..PitchConfig::default()
        })
        .expect("valid config");
        group.bench_function(format!("pyin_hop256_res{resolution}"), |b| {
            b.iter(|| tracker.track(samples).expect("tracks"))
        });
    }
    let tracker = PitchTracker::new(PitchConfig::default()).expect("valid config");
    let track = tracker.track(samples).expect("tracks");
    group.bench_function("segment_notes", |b| {
        b.iter(|| segment_notes(&track, samples, 22_050, &NoteConfig::default()).expect("notes"))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
