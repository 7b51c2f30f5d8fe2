//! pYIN and note segmentation on 180 s of synthetic violin (a corpus étude at 100 bpm, the
//! corpus's bowed-string synthesizer) at 22 050 Hz, hop 256.
//!
//! `cargo bench -p pitch-track --bench pitch`
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use corpus::item::clean_etude;
use criterion::{criterion_group, criterion_main, Criterion};
use pitch_track::{segment_notes, NoteConfig, PitchConfig, PitchTracker};

fn bench(c: &mut Criterion) {
    let item = clean_etude(3, 180.0, (100.0, 100.0)).expect("corpus item renders");
    let samples = &item.audio[..(180 * 22_050).min(item.audio.len())];
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
