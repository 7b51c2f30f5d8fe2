//! Criterion bench of `Pipeline::generate` (Method 2, embedded models) on 60 s of audio.
//!
//! `cargo bench --bench generate`
#![allow(clippy::expect_used, missing_docs)]

use corpus::etude::{generate as etude, EtudeConfig};
use corpus::render::{BowedStringSynth, RenderSettings, Renderer};
use corpus::timing::play;
use criterion::{criterion_group, criterion_main, Criterion};
use violin_skeleton::{Audio, Pipeline};

fn sixty_seconds() -> Audio {
    let cfg = EtudeConfig {
        target_s: 60.0,
        ..EtudeConfig::default()
    };
    let mut timeline = play(&etude(4, &cfg), 4);
    timeline.assign_fingering(&violin_skeleton::fingering::OptimalPlanner::default());
    let settings = RenderSettings {
        sample_rate_hz: 44_100,
        tuning_cents: 0.0,
        seed: 4,
    };
    let samples = BowedStringSynth::default()
        .render(&timeline, &settings)
        .expect("render");
    let n = 60 * 44_100;
    Audio::new(samples.into_iter().take(n).collect(), 44_100).expect("audio")
}

fn generate(c: &mut Criterion) {
    let audio = sixty_seconds();
    let pipeline = Pipeline::default();
    pipeline.generate(&audio).expect("warm-up");
    let mut group = c.benchmark_group("generate_60s_44k1");
    group.sample_size(10);
    group.bench_function("rules", |b| {
        b.iter(|| pipeline.generate(&audio).expect("generate"))
    });
    group.finish();
}

criterion_group!(benches, generate);
criterion_main!(benches);
