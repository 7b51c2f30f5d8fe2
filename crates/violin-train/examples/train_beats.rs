//! Trains beat-net (issue 20) on a corpus's `train` split, keeping the epoch with the best
//! validation score (`val` split); the shipped weights were made with
//!
//! `CANDLE_NUM_THREADS=1 RAYON_NUM_THREADS=1 cargo run --release -p violin-train --example
//! train_beats -- /work/data/corpus-10h crates/beat-net/weights/beat-net.safetensors [CONFIG.json]`
//!
//! CONFIG.json: any subset of `beat_net::TrainConfig` (defaults otherwise). Each
//! `--extra-train DIR` adds the train split of another corpus (built with another seed: the
//! same training works, other excerpts, tempi and violins); validation stays the first
//! corpus's.

use std::path::PathBuf;

use beat_net::TrainConfig;
use violin_train::beat_data::{load_beat_corpus, load_beat_train_split};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let usage =
        "usage: train_beats CORPUS_DIR OUT.safetensors [CONFIG.json] [--extra-train DIR]...";
    let mut positional = Vec::new();
    let mut extra: Vec<PathBuf> = Vec::new();
    while let Some(a) = args.next() {
        if a == "--extra-train" {
            extra.push(args.next().ok_or(usage)?.into());
        } else {
            positional.push(a);
        }
    }
    let mut positional = positional.into_iter();
    let data_dir: PathBuf = positional.next().ok_or(usage)?.into();
    let out: PathBuf = positional.next().ok_or(usage)?.into();
    let mut cfg: TrainConfig = match positional.next() {
        Some(p) => serde_json::from_str(&std::fs::read_to_string(p)?)?,
        None => TrainConfig::default(),
    };
    cfg.data_description = format!(
        "{} (train split; val for early stopping)",
        data_dir.display()
    );
    for dir in &extra {
        cfg.data_description += &format!(" + {} (train split)", dir.display());
    }
    let t0 = std::time::Instant::now();
    let mut data = load_beat_corpus(&data_dir, &|_, _| {})?;
    for dir in &extra {
        data.train.extend(load_beat_train_split(dir, &|_, _| {})?);
    }
    println!(
        "loaded {} train and {} val recordings in {:.0} s",
        data.train.len(),
        data.val.len(),
        t0.elapsed().as_secs_f64()
    );
    println!("config: {}", serde_json::to_string(&cfg)?);
    let report = beat_net::train(&data, &cfg, &out, &mut |p| {
        if let Some(v) = p.val {
            println!(
                "epoch {}: loss {:.4}, val loss {:.4}, beat F {:.3}, downbeat F {:.3} ({:.0} s)",
                p.epoch + 1,
                p.loss,
                v.loss,
                v.beat_f,
                v.downbeat_f,
                p.elapsed_s
            );
        } else if p.step.is_multiple_of(20) {
            println!(
                "  epoch {} step {}/{}: loss {:.4} ({:.0} s)",
                p.epoch + 1,
                p.step,
                p.steps,
                p.loss,
                p.elapsed_s
            );
        }
    })?;
    println!("{}", serde_json::to_string_pretty(&report)?);
    Ok(())
}
