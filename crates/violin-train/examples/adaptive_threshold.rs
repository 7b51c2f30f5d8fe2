//! Does a per-recording change threshold help violins the network is less sure of? On a
//! violin it never heard, the ensemble's change probabilities are lower and its misses
//! outnumber its false changes (held-out violins: precision 0.91, recall 0.76). This
//! decoder lowers the threshold of a recording whose confident peaks are low: with `L` the
//! `q`-quantile of the heights of its local maxima at or above 0.2, the threshold is
//! `min(threshold, r·L)`. Measured on the validation items of a corpus (training violins)
//! and of the same items rendered with another violin (`corpus … --validation-violin`),
//! bow-change F1 at ±2 frames, events pooled; no test item is read.
//!
//! `cargo run --release -p violin-train --example adaptive_threshold -- CORPUS VAL_VIOLIN_CORPUS`

use std::path::{Path, PathBuf};

use bowing_net::data::Recording;
use bowing_net::metrics::{match_events, Counts};
use bowing_net::{BowChangeDetector, Decoder};
use violin_train::bowing_data::load_dataset;

fn validation_items(dir: &Path) -> Result<Vec<Recording>, Box<dyn std::error::Error>> {
    Ok(load_dataset(dir, &|_, _| {})?.val)
}

/// The shipped ensemble's change probabilities of every recording.
fn ensemble(recs: &[Recording]) -> Result<Vec<Vec<f32>>, Box<dyn std::error::Error>> {
    let cnn = BowChangeDetector::pretrained()?;
    let net = bowing_net::BowingModel::pretrained_strokes()?;
    recs.iter()
        .map(|r| {
            let mut p = net.frame_outputs(r.mel_db.view())?.change;
            bowing_net::stroke::average_changes(&mut p, &cnn.frame_probabilities(r.mel_db.view())?);
            Ok(p)
        })
        .collect()
}

/// The `q`-quantile of the heights of the local maxima of `p` at or above 0.2 (1 when
/// there are none, so the threshold is left alone).
fn peak_level(p: &[f32], q: f64) -> f32 {
    let n = p.len();
    let mut peaks: Vec<f32> = (0..n)
        .filter(|&i| p[i] >= 0.2 && (i == 0 || p[i] >= p[i - 1]) && (i + 1 == n || p[i] > p[i + 1]))
        .map(|i| p[i])
        .collect();
    if peaks.is_empty() {
        return 1.0;
    }
    peaks.sort_by(f32::total_cmp);
    peaks[((peaks.len() - 1) as f64 * q).round() as usize]
}

/// Pooled counts of the adaptive decoder (`r` = ∞: the plain decoder).
fn counts(probs: &[Vec<f32>], recs: &[Recording], d: Decoder, r: f32, q: f64) -> Counts {
    let mut c = Counts::default();
    for (p, rec) in probs.iter().zip(recs) {
        let threshold = d.threshold.min(r * peak_level(p, q));
        let own = Decoder { threshold, ..d };
        c.add(&match_events(&own.pick(p), &rec.changes, 2));
    }
    c
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<PathBuf> = std::env::args().skip(1).map(PathBuf::from).collect();
    let [corpus, other] = args.as_slice() else {
        return Err("usage: adaptive_threshold CORPUS VAL_VIOLIN_CORPUS".into());
    };
    let heard = validation_items(corpus)?;
    let unheard = validation_items(other)?;
    let (p, q_) = (ensemble(&heard)?, ensemble(&unheard)?);
    let all_p: Vec<Vec<f32>> = p.iter().chain(&q_).cloned().collect();
    let all_r: Vec<Recording> = heard.iter().chain(&unheard).cloned().collect();
    println!("| threshold | spacing | r | q | training violins P/R/F1 | unheard violin P/R/F1 | both F1 |");
    println!("|---|---|---|---|---|---|---|");
    let row = |d: Decoder, r: f32, q: f64| {
        let (a, b) = (counts(&p, &heard, d, r, q), counts(&q_, &unheard, d, r, q));
        let both = counts(&all_p, &all_r, d, r, q).f1();
        let prf = |c: &Counts| format!("{:.3}/{:.3}/{:.3}", c.precision(), c.recall(), c.f1());
        (
            both,
            format!(
                "| {} | {} | {r} | {q} | {} | {} | {both:.3} |",
                d.threshold,
                d.min_spacing_frames,
                prf(&a),
                prf(&b)
            ),
        )
    };
    let shipped = bowing_net::BowingModel::pretrained_strokes()?
        .ensemble_decoder()
        .ok_or("no ensemble decoder")?;
    let (base, line) = row(shipped, f32::INFINITY, 0.5);
    println!("{line}");
    let mut best = (base, line);
    for spacing in 2..=4 {
        for k in 6..=16 {
            let d = Decoder {
                threshold: 0.05 * k as f32,
                min_spacing_frames: spacing,
            };
            for r in [0.5f32, 0.6, 0.7, 0.8, 0.9] {
                for q in [0.5, 0.75, 0.9] {
                    let (f, line) = row(d, r, q);
                    if f > best.0 {
                        best = (f, line);
                    }
                }
            }
        }
    }
    println!("{}", best.1);
    eprintln!("shipped decoder {base:.3}, best adaptive {:.3}", best.0);
    Ok(())
}
