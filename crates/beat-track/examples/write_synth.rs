//! Writes labelled synthetic violin pieces for `scripts/compare_analysis_librosa.py`:
//! `DIR/synth_SEED.wav` (16-bit, 22 050 Hz) and `DIR/synth_SEED.json` with the ground truth
//! (notes, beats, downbeats, tempo, metre, and the reference f0 on a 256-sample hop grid,
//! 0 = unvoiced).
//!
//! ```sh
//! cargo run --release -p beat-track --example write_synth -- DIR [COUNT] [SECONDS] [LONG_SECONDS]
//! ```
//! writes COUNT (default 8) pieces of about SECONDS (default 30) from `SynthConfig::varied`
//! (seeds 1..=COUNT), and, when LONG_SECONDS is given, `DIR/synth_long.wav` of that length
//! (4/4 at 100 bpm, for timing).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use pitch_track::synth::{render, SynthConfig, SynthPiece};

const HOP: usize = 256;

fn write_wav(path: &Path, piece: &SynthPiece) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: piece.sample_rate_hz,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).expect("create wav");
    for &s in &piece.samples {
        w.write_sample((s.clamp(-1.0, 1.0) * 32_767.0) as i16)
            .expect("write sample");
    }
    w.finalize().expect("finish wav");
}

fn write_truth(path: &Path, piece: &SynthPiece) {
    let hop_s = HOP as f64 / f64::from(piece.sample_rate_hz);
    let frames = 1 + piece.samples.len() / HOP;
    let truth = serde_json::json!({
        "duration_s": piece.duration_s(),
        "tempo_bpm": piece.tempo_bpm,
        "beats_per_bar": piece.time_signature.beats_per_bar,
        "subdivisions": piece.time_signature.subdivisions,
        "notes": piece.notes.iter().map(|n| serde_json::json!({
            "onset_s": n.onset_s, "offset_s": n.offset_s, "midi": n.midi, "slurred": n.slurred
        })).collect::<Vec<_>>(),
        "beats_s": piece.beats_s,
        "downbeats_s": piece.downbeats_s,
        "f0_hop_s": hop_s,
        "f0_hz": piece.reference_f0(hop_s, frames),
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
        let piece = render(&SynthConfig::varied(seed, seconds)).expect("render");
        write_wav(&dir.join(format!("synth_{seed}.wav")), &piece);
        write_truth(&dir.join(format!("synth_{seed}.json")), &piece);
        eprintln!(
            "synth_{seed}: {:.1} s, {:.0} bpm, {}/{}, {} notes",
            piece.duration_s(),
            piece.tempo_bpm,
            piece.time_signature.beats_per_bar,
            if piece.time_signature.subdivisions == 3 {
                8
            } else {
                4
            },
            piece.notes.len()
        );
    }
    if let Some(long) = args.get(3) {
        let long: f64 = long.parse().expect("LONG_SECONDS is a number");
        let bars = (long / 2.4).ceil() as usize; // 4/4 at 100 bpm: 2.4 s per bar
        let mut piece = render(&SynthConfig {
            seed: 3,
            tempo_bpm: 100.0,
            bars,
            ..SynthConfig::default()
        })
        .expect("render");
        piece
            .samples
            .truncate((long * f64::from(piece.sample_rate_hz)) as usize);
        write_wav(&dir.join("synth_long.wav"), &piece);
        eprintln!("synth_long: {:.1} s", piece.duration_s());
    }
}
