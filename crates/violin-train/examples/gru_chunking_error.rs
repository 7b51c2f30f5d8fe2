//! How far chunked inference (crate docs, `Chunking`) is from the sequential run, for a
//! range of warm-ups, on real corpus audio: the clips of one split are joined into
//! recordings of `--seconds` (default 180 s) and each is run both ways.
//!
//! ```sh
//! cargo run --release -p violin-train --example gru_chunking_error -- \
//!     --data /work/data/corpus-mix [--weights W.safetensors] [--split test] [--seconds 180]
//! ```
//!
//! Prints, per warm-up, the mean, 99th-percentile and largest |difference| of the joints in
//! pixels, over every frame and coordinate.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::error::Error;
use std::path::PathBuf;

use gru_baseline::features::mel_frames;
use gru_baseline::{Chunking, GruBaseline};
use ndarray::{concatenate, Array2, Axis};
use violin_train::gru_data::corpus::read_manifest;

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let (mut data, mut weights, mut split, mut seconds) = (None, None, "test".to_string(), 180.0);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--data" => data = args.next().map(PathBuf::from),
            "--weights" => weights = args.next().map(PathBuf::from),
            "--split" => split = args.next().unwrap_or_default(),
            "--seconds" => seconds = args.next().ok_or("--seconds N")?.parse()?,
            other => return Err(format!("unknown argument {other}").into()),
        }
    }
    let root = data.ok_or("--data DIR (a corpus) is required")?;
    let net = match &weights {
        Some(p) => GruBaseline::load(p)?,
        None => GruBaseline::pretrained()?,
    };
    let manifest = read_manifest(&root)?;
    let mut recordings: Vec<Array2<f32>> = Vec::new();
    let mut current: Vec<Array2<f32>> = Vec::new();
    let target_frames = (seconds * 30.0) as usize;
    for item in manifest
        .items
        .iter()
        .filter(|i| format!("{:?}", i.split).eq_ignore_ascii_case(&split))
    {
        let audio = dsp_mel::load_audio(root.join(&item.dir).join("audio.wav"))?;
        current.push(mel_frames(&audio)?);
        if current.iter().map(|m| m.nrows()).sum::<usize>() >= target_frames {
            let views: Vec<_> = current.iter().map(|m| m.view()).collect();
            recordings.push(concatenate(Axis(0), &views)?);
            current.clear();
        }
    }
    let frames: usize = recordings.iter().map(|r| r.nrows()).sum();
    println!(
        "{} recordings of >= {seconds} s from the {split} split ({:.1} min)\n",
        recordings.len(),
        frames as f64 / 1800.0
    );
    let torso = net.target_space().torso_px;
    let exact: Vec<Array2<f32>> = recordings
        .iter()
        .map(|r| net.predict_normalized_exact(r.view()))
        .collect::<Result<_, _>>()?;
    println!("| warm-up (frames) | mean px | p99 px | max px |");
    println!("|---|---|---|---|");
    for warmup in [0, 15, 30, 45, 60, 90, 120, 180] {
        let chunking = Chunking {
            warmup_frames: warmup,
            ..Chunking::default()
        };
        let mut diffs: Vec<f32> = Vec::new();
        for (r, e) in recordings.iter().zip(&exact) {
            let c = net.predict_normalized_with(r.view(), &chunking)?;
            diffs.extend((&c - e).iter().map(|d| d.abs() * torso));
        }
        diffs.sort_by(f32::total_cmp);
        let mean = diffs.iter().map(|&d| f64::from(d)).sum::<f64>() / diffs.len() as f64;
        let p99 = diffs[diffs.len() * 99 / 100];
        println!(
            "| {warmup} | {mean:.4} | {p99:.3} | {:.3} |",
            diffs.last().copied().unwrap_or(0.0)
        );
    }
    Ok(())
}
