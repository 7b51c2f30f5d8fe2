//! Chooses the bar-pointer decoder's bar-length prior (log-probability per frame added to
//! each bar length's path before the most likely one is taken) on a corpus's
//! **validation** split only (the test sets are never read): each item is decoded once
//! per bar length, then priors are searched coordinate-wise for the best metre accuracy
//! that keeps beat and downbeat F.
//!
//! `cargo run --release -p violin-train --example tune_meter_prior -- CORPUS [WEIGHTS]`

use std::path::PathBuf;

use beat_net::BeatActivation;
use beat_track::bar_pointer::{decode, BarPointerBeats, BarPointerConfig};
use beat_track::eval::{beat_prf, trim_beats};
use corpus::manifest::Split;
use violin_train::beat_data::read_first_column;
use violin_train::bowing_data::read_manifest;
use violin_train::feature_cache::cached_mel30;

struct Item {
    per_bar: Vec<BarPointerBeats>,
    frames: f64,
    beats: Vec<f64>,
    downbeats: Vec<f64>,
    bar: Option<u64>,
}

/// (beat F, downbeat F, metre accuracy) with `prior` per bar length (frames × prior added).
fn score(items: &[Item], prior: &[f64]) -> (f64, f64, f64) {
    let (mut bf, mut df, mut meter) = (0.0, 0.0, 0usize);
    for it in items {
        let best = (0..it.per_bar.len())
            .max_by(|&a, &b| {
                let s = |k: usize| {
                    it.per_bar[k]
                        .log_probability
                        .first()
                        .copied()
                        .unwrap_or(f64::NEG_INFINITY)
                        + prior[k] * it.frames
                };
                s(a).total_cmp(&s(b))
            })
            .unwrap_or(0);
        let out = &it.per_bar[best];
        let tr = |v: &[f64]| trim_beats(v, 5.0);
        bf += beat_prf(&tr(&it.beats), &tr(&out.beats_s), 0.07).f_measure;
        df += beat_prf(&tr(&it.downbeats), &tr(&out.downbeats_s), 0.07).f_measure;
        meter += usize::from(it.bar == Some(out.beats_per_bar as u64) && !out.beats_s.is_empty());
    }
    let n = items.len().max(1) as f64;
    (bf / n, df / n, meter as f64 / n)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let dir: PathBuf = args
        .next()
        .ok_or("usage: tune_meter_prior CORPUS_DIR [WEIGHTS]")?
        .into();
    let net = match args.next() {
        Some(p) => BeatActivation::load(&PathBuf::from(p))?,
        None => BeatActivation::pretrained()?,
    };
    let base = BarPointerConfig {
        bar_length_prior_per_frame: Vec::new(),
        ..BarPointerConfig::default()
    };
    let manifest = read_manifest(&dir)?;
    let mut items = Vec::new();
    for it in manifest.items.iter().filter(|it| it.split == Split::Val) {
        let d = dir.join(&it.dir);
        let mel = cached_mel30(&d, &corpus::layout::item_audio(&d))?;
        let labels: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.join("labels.json"))?)?;
        let act = net.activations(mel.view())?;
        let per_bar = base
            .beats_per_bar
            .iter()
            .map(|&n| {
                let cfg = BarPointerConfig {
                    beats_per_bar: vec![n],
                    ..base.clone()
                };
                decode(&act.beat, &act.downbeat, &cfg)
            })
            .collect::<Result<Vec<_>, _>>()?;
        items.push(Item {
            per_bar,
            frames: act.beat.len() as f64,
            beats: read_first_column(&d.join("beats.txt"))?,
            downbeats: read_first_column(&d.join("downbeats.txt"))?,
            bar: labels["beats_per_bar"].as_u64(),
        });
    }
    let mut prior = vec![0.0; base.beats_per_bar.len()];
    let start = score(&items, &prior);
    println!(
        "{} validation items; bar lengths {:?}",
        items.len(),
        base.beats_per_bar
    );
    println!(
        "no prior: beat F {:.3}  downbeat F {:.3}  metre {:.3}",
        start.0, start.1, start.2
    );
    let grid: Vec<f64> = (-12..=12).map(|k| f64::from(k) * 0.0025).collect();
    let objective = |s: (f64, f64, f64)| s.2 + s.1;
    let mut best = objective(start);
    for _round in 0..3 {
        for k in 0..prior.len() {
            for &v in &grid {
                let mut p = prior.clone();
                p[k] = v;
                let s = score(&items, &p);
                if objective(s) > best + 1e-9 {
                    best = objective(s);
                    prior = p;
                }
            }
        }
    }
    let s = score(&items, &prior);
    println!(
        "prior {prior:?}: beat F {:.3}  downbeat F {:.3}  metre {:.3}",
        s.0, s.1, s.2
    );
    Ok(())
}
