//! Writes an ensemble of beat networks (issue 20): files from `train_beats` (same shape,
//! e.g. different seeds) whose per-frame probabilities `beat_net::BeatActivation` averages.
//!
//! `cargo run --release -p violin-train --example ensemble_beats -- OUT.safetensors
//! SEED1.safetensors SEED2.safetensors [...]`

use std::path::PathBuf;

use beat_net::BeatActivation;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let usage = "usage: ensemble_beats OUT.safetensors IN.safetensors IN.safetensors [...]";
    let mut args = std::env::args().skip(1).map(PathBuf::from);
    let out = args.next().ok_or(usage)?;
    let inputs: Vec<PathBuf> = args.collect();
    if inputs.len() < 2 {
        return Err(usage.into());
    }
    let parts = inputs
        .iter()
        .map(|p| BeatActivation::load(p))
        .collect::<Result<Vec<_>, _>>()?;
    let ensemble = BeatActivation::ensemble(parts)?;
    ensemble.save(&out)?;
    println!(
        "{}: {} networks averaged",
        out.display(),
        ensemble.member_count()
    );
    Ok(())
}
