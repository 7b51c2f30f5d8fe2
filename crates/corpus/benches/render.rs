//! Render speed of the built-in synthesizer on one 30 s étude (single thread).
//!
//! `cargo bench -p corpus --bench render`
#![allow(clippy::expect_used, missing_docs)]

use corpus::etude::{generate, EtudeConfig};
use corpus::render::{BowedStringSynth, RenderSettings, Renderer};
use corpus::timing::play;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

fn render(c: &mut Criterion) {
    let mut timeline = play(&generate(1, &EtudeConfig::default()), 1);
    timeline.assign_fingering(&fingering::OptimalPlanner::default());
    eprintln!("étude length: {:.1} s", timeline.duration_s);
    let synth = BowedStringSynth::default();
    let mut group = c.benchmark_group("builtin_render_30s");
    group.sample_size(10);
    for rate in [22_050u32, 48_000] {
        let settings = RenderSettings {
            sample_rate_hz: rate,
            tuning_cents: 0.0,
            seed: 1,
        };
        group.bench_with_input(BenchmarkId::from_parameter(rate), &settings, |b, s| {
            b.iter(|| synth.render(&timeline, s).expect("render"))
        });
    }
    group.finish();
}

criterion_group!(benches, render);
criterion_main!(benches);
