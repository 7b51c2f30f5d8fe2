//! Synthesis speed: 3 minutes of motion (5 400 frames at 30 fps).
//!
//! `cargo bench -p motion-synth --bench synth`
#![allow(missing_docs, clippy::unwrap_used, clippy::expect_used)]

use criterion::{criterion_group, criterion_main, Criterion};
use fingering::OptimalPlanner;
use motion_synth::{bow, synthesize, BowPolicy, SynthConfig};
use performance::{ArousalCurve, Performance};

/// Three minutes of eighth notes at 100 bpm over two octaves of G major, a bow change
/// every two notes, beats, downbeats and a slow arousal wave; fingerings planned.
fn three_minutes() -> Performance {
    let scale = [55u8, 57, 59, 60, 62, 64, 66, 67, 69, 71, 72, 74, 76, 78, 79];
    let duration = 180.0;
    let eighth = 0.3;
    let n = (duration / eighth) as usize;
    let mut b = Performance::builder(duration);
    let mut changes = Vec::new();
    for i in 0..n {
        let k = i % 28;
        let midi = scale[if k < 14 { k } else { 28 - k }];
        let t = i as f64 * eighth;
        b = b.note(t, t + eighth * 0.95, midi);
        if i % 2 == 0 && i > 0 {
            changes.push(t);
        }
    }
    let beats: Vec<f64> = (0..300).map(|i| i as f64 * 0.6).collect();
    let downbeats = beats.iter().copied().step_by(4).collect();
    let arousal = (0..360).map(|i| (i as f32 / 40.0).sin() * 0.8).collect();
    b.bow_changes(changes)
        .beats(beats)
        .downbeats(downbeats)
        .arousal(ArousalCurve::deam(arousal))
        .build()
        .unwrap()
        .with_fingering(&OptimalPlanner::default())
        .unwrap()
}

fn bench(c: &mut Criterion) {
    let perf = three_minutes();
    let cfg = SynthConfig::default();
    assert_eq!(synthesize(&perf, &cfg).unwrap().len(), 5400);
    c.bench_function("synthesize 3 min (5400 frames)", |b| {
        b.iter(|| synthesize(std::hint::black_box(&perf), &cfg).unwrap())
    });
    let changes = bow::change_frames(perf.bow_changes_s(), 30.0, 5400);
    c.bench_function("bow planner 3 min", |b| {
        b.iter(|| {
            bow::plan_bow(
                std::hint::black_box(&changes),
                5400,
                &[],
                &BowPolicy::default(),
            )
            .unwrap()
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
