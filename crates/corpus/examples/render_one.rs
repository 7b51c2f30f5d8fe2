//! Renders one étude with the built-in synthesizer and writes `audio.wav` and `notes.tsv`.
//!
//! `cargo run --release -p corpus --example render_one -- OUT_DIR [SEED]`
#![allow(clippy::unwrap_used, clippy::expect_used)]

use corpus::etude::{generate, EtudeConfig};
use corpus::render::{BowedStringSynth, RenderSettings, Renderer};
use corpus::timing::play;
use fingering::OptimalPlanner;
use std::io::Write;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let out = std::path::PathBuf::from(args.get(1).cloned().unwrap_or_else(|| "/tmp/etude".into()));
    let seed: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1);
    std::fs::create_dir_all(&out).unwrap();
    let etude = generate(seed, &EtudeConfig::default());
    let mut timeline = play(&etude, seed);
    timeline.assign_fingering(&OptimalPlanner::default());
    let settings = RenderSettings {
        sample_rate_hz: 22_050,
        tuning_cents: 0.0,
        seed,
    };
    let t0 = Instant::now();
    let audio = BowedStringSynth::default()
        .render(&timeline, &settings)
        .unwrap();
    let dt = t0.elapsed().as_secs_f64();
    eprintln!(
        "{} {} bpm, {:.1} s rendered in {:.1} ms ({:.0}x real time)",
        etude.meter.name(),
        etude.tempo_bpm.round(),
        timeline.duration_s,
        dt * 1e3,
        timeline.duration_s / dt
    );
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 22_050,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let mut w = hound::WavWriter::create(out.join("audio.wav"), spec).unwrap();
    for s in &audio {
        w.write_sample(*s).unwrap();
    }
    w.finalize().unwrap();
    let mut f = std::fs::File::create(out.join("notes.tsv")).unwrap();
    for n in &timeline.notes {
        writeln!(
            f,
            "{:.4}\t{:.4}\t{}\t{}",
            n.note.onset_s,
            n.note.offset_s,
            n.note.midi,
            u8::from(n.bow_change)
        )
        .unwrap();
    }
}
