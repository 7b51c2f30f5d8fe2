//! The bar-pointer decoder on 180 s of activations at 30 fps (beats at 100 bpm with a
//! slow tempo drift, 3/4), bar lengths 1–4 as shipped.
//!
//! `cargo bench -p beat-track --bench bar_pointer`
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use beat_track::bar_pointer::{decode, decode_with_downbeat_evidence, BarPointerConfig};
use criterion::{criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    let frames = 180 * 30;
    let (mut beat, mut down) = (vec![0.03f32; frames], vec![0.02f32; frames]);
    let mut t = 0.5f64;
    let mut k = 0usize;
    while t < 179.0 {
        let f = (t * 30.0).round() as usize;
        if k.is_multiple_of(3) {
            down[f] = 0.8;
        } else {
            beat[f] = 0.8;
        }
        t += 0.6 * (1.0 + 0.1 * (t / 20.0).sin());
        k += 1;
    }
    let cfg = BarPointerConfig::default();
    let mut group = c.benchmark_group("bar_pointer_180s");
    group.sample_size(20);
    group.bench_function("decode_bars_1_to_4", |b| {
        b.iter(|| decode(&beat, &down, &cfg).expect("decodes"))
    });
    // As the analysis calls it: a bow change on every second beat phases the bars (one
    // more decoding of the chosen bar length).
    let mut bows = vec![0.0f32; frames];
    for (f, _) in beat
        .iter()
        .zip(&down)
        .enumerate()
        .filter(|(_, (b, d))| b.max(**d) > 0.5)
        .step_by(2)
    {
        bows[f] = 1.0;
    }
    group.bench_function("decode_phased_on_bow_changes", |b| {
        b.iter(|| decode_with_downbeat_evidence(&beat, &down, &bows, &cfg).expect("decodes"))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
