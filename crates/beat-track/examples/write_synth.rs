//! Writes labelled synthetic violin pieces for `scripts/compare_analysis_librosa.py`: corpus
//! études (`corpus::item::make_item`, seeds 1..=COUNT) rendered by the corpus's bowed-string
//! synthesizer without augmentation, as `DIR/synth_SEED.wav` (16-bit, 22 050 Hz) and
//! `DIR/synth_SEED.json` with the ground truth (notes, beats, downbeats, tempo, metre, and
//! the reference f0 on a 256-sample hop grid with the frames the labels decide:
//! `corpus::reference::reference_f0`; 0 = unvoiced, `f0_keep` false = not scored).
//!
//! ```sh
//! cargo run --release -p beat-track --example write_synth -- DIR [COUNT] [SECONDS] [LONG_SECONDS]
//! ```
//! writes COUNT (default 8) pieces of about SECONDS (default 30), and, when LONG_SECONDS is
//! given, `DIR/synth_long.wav` of that length (an étude at 100 bpm, for timing).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use corpus::etude::EtudeConfig;
use corpus::item::{make_item, CorpusItem, RendererKind};
use corpus::reference::reference_f0;
use corpus::render::BowedStringSynth;

const HOP: usize = 256;
const SR: u32 = 22_050;

fn item(seed: u64, etude: &EtudeConfig) -> CorpusItem {
    let item = make_item(
        seed,
        etude,
        &BowedStringSynth::default(),
        RendererKind::Builtin,
        false,
    )
    .expect("corpus item renders");
    assert_eq!(item.augmentation.sample_rate_hz, SR);
    item
}

fn write_wav(path: &Path, samples: &[f32]) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: SR,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).expect("create wav");
    for &s in samples {
        w.write_sample((s.clamp(-1.0, 1.0) * 32_767.0) as i16)
            .expect("write sample");
    }
    w.finalize().expect("finish wav");
}

fn write_truth(path: &Path, item: &CorpusItem) {
    let hop_s = HOP as f64 / f64::from(SR);
    let frames = 1 + item.audio.len() / HOP;
    let tl = &item.timeline;
    let f0 = reference_f0(tl, item.augmentation.tuning_cents, hop_s, frames);
    let truth = serde_json::json!({
        "duration_s": item.audio.len() as f64 / f64::from(SR),
        "tempo_bpm": tl.tempo_bpm,
        "beats_per_bar": item.time_signature.meter().beats_per_bar,
        "subdivisions": item.time_signature.meter().subdivisions,
        "notes": tl.notes.iter().enumerate().map(|(i, n)| serde_json::json!({
            "onset_s": n.note.onset_s, "offset_s": n.note.offset_s, "midi": n.note.midi,
            "slurred": i > 0 && !n.bow_change
        })).collect::<Vec<_>>(),
        "beats_s": tl.beats_s,
        "downbeats_s": tl.downbeats_s,
        "f0_hop_s": hop_s,
        "f0_hz": f0.iter().map(|f| f.unwrap_or(0.0)).collect::<Vec<_>>(),
        "f0_keep": f0.iter().map(Option::is_some).collect::<Vec<_>>(),
    });
    std::fs::write(path, serde_json::to_string(&truth).expect("json")).expect("write json");
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(dir) = args.first() else {
        eprintln!("usage: write_synth DIR [COUNT] [SECONDS] [LONG_SECONDS]");
        std::process::exit(2);
    };
    let count: u64 = args
        .get(1)
        .map_or(8, |s| s.parse().expect("COUNT is a number"));
    let seconds: f64 = args
        .get(2)
        .map_or(30.0, |s| s.parse().expect("SECONDS is a number"));
    let dir = Path::new(dir);
    std::fs::create_dir_all(dir).expect("create output folder");
    for seed in 1..=count {
        let etude = EtudeConfig {
            target_s: seconds,
            ..EtudeConfig::default()
        };
        let item = item(seed, &etude);
        write_wav(&dir.join(format!("synth_{seed}.wav")), &item.audio);
        write_truth(&dir.join(format!("synth_{seed}.json")), &item);
        eprintln!(
            "synth_{seed}: {:.1} s, {:.0} bpm, {}, {} notes",
            item.audio.len() as f64 / f64::from(SR),
            item.timeline.tempo_bpm,
            item.time_signature,
            item.timeline.notes.len()
        );
    }
    if let Some(long) = args.get(3) {
        let long: f64 = long.parse().expect("LONG_SECONDS is a number");
        let etude = EtudeConfig {
            target_s: long,
            tempo_bpm: (100.0, 100.0),
            ..EtudeConfig::default()
        };
        let mut audio = item(3, &etude).audio;
        audio.truncate((long * f64::from(SR)) as usize);
        write_wav(&dir.join("synth_long.wav"), &audio);
        eprintln!("synth_long: {:.1} s", audio.len() as f64 / f64::from(SR));
    }
}
