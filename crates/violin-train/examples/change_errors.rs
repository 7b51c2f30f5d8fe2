//! Where the shipped bow-change detection errs on the validation split (test sets never
//! read): misses by the time since the previous labelled change and by whether the change
//! starts a new note or repeats one; false changes by whether they fall on a slurred note
//! change, a plain note onset, or neither.
//!
//! ```text
//! cargo run --release -p violin-train --example change_errors -- CORPUS
//! ```

use std::path::PathBuf;

use bowing_net::metrics::matched_predictions;
use bowing_net::BowingModel;
use violin_train::bowing_data::{load_dataset, read_manifest};

const FPS: f64 = 30.0;

fn near(frames: &[usize], f: usize, tol: usize) -> bool {
    frames.iter().any(|&x| x.abs_diff(f) <= tol)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let corpus = PathBuf::from(
        std::env::args()
            .nth(1)
            .ok_or("usage: change_errors CORPUS")?,
    );
    let data = load_dataset(&corpus, &|_, _| {})?;
    let manifest = read_manifest(&corpus)?;
    let etudes = manifest.etude_dirs();
    let model = BowingModel::pretrained()?;
    // [étude?][interval bin] -> (labelled, missed)
    let bins = [0.0, 0.15, 0.25, 0.4, 0.7, 1.2, f64::INFINITY];
    let mut by_gap = [[(0usize, 0usize); 6]; 2];
    // false changes: [étude?] -> (slurred onset, other onset, no onset)
    let mut false_kind = [(0usize, 0usize, 0usize); 2];
    let mut slurred_total = [0usize; 2];
    // fast misses (gap <= 4 frames): [gap 1..=4] -> (labelled, missed, missed with a local
    // maximum within ±1 frame below the threshold, missed inside a plateau >= threshold)
    let mut fast = [(0usize, 0usize, 0usize, 0usize); 5];
    // runs of frames >= 0.65: [length] -> labelled changes inside (0, 1, 2, 3, 4+)
    let mut run_table = vec![[0usize; 5]; 25];
    for r in &data.val {
        let e = usize::from(etudes.contains(r.name.as_str()));
        let bowed = model.analyze_mel(r.mel_db.view())?;
        let pred: Vec<usize> = bowed
            .bow_changes_s
            .iter()
            .map(|t| (t * FPS).round() as usize)
            .collect();
        {
            let p = &bowed.frames.change;
            let mut i = 0;
            while i < p.len() {
                if p[i] < 0.65 {
                    i += 1;
                    continue;
                }
                let a = i;
                while i < p.len() && p[i] >= 0.65 {
                    i += 1;
                }
                let inside = r.changes.iter().filter(|&&c| c >= a && c < i).count();
                run_table[(i - a).min(24)][inside.min(4)] += 1;
            }
        }
        let hit_truth = matched_predictions(&r.changes, &pred, 2);
        for (k, (&c, &hit)) in r.changes.iter().zip(&hit_truth).enumerate() {
            let gap = if k == 0 {
                f64::INFINITY
            } else {
                (c - r.changes[k - 1]) as f64 / FPS
            };
            let b = bins
                .windows(2)
                .position(|w| gap >= w[0] && gap < w[1])
                .unwrap_or(5);
            by_gap[e][b].0 += 1;
            by_gap[e][b].1 += usize::from(!hit);
            if k > 0 && c - r.changes[k - 1] <= 4 {
                let g = c - r.changes[k - 1];
                let p = &bowed.frames.change;
                fast[g].0 += 1;
                if !hit {
                    fast[g].1 += 1;
                    let lo = c.saturating_sub(1);
                    let hi = (c + 1).min(p.len().saturating_sub(2));
                    let local_max = (lo.max(1)..=hi).any(|i| p[i] >= p[i - 1] && p[i] > p[i + 1]);
                    let high = p.get(c).copied().unwrap_or(0.0) >= 0.65;
                    if high {
                        fast[g].3 += 1;
                    } else if local_max {
                        fast[g].2 += 1;
                    }
                }
            }
        }
        let matched = matched_predictions(&pred, &r.changes, 2);
        slurred_total[e] += r.slurred.len();
        for (&p, &m) in pred.iter().zip(&matched) {
            if m {
                continue;
            }
            if near(&r.slurred, p, 2) {
                false_kind[e].0 += 1;
            } else if near(&r.onsets, p, 2) {
                false_kind[e].1 += 1;
            } else {
                false_kind[e].2 += 1;
            }
        }
    }
    for (len, counts) in run_table.iter().enumerate().skip(1) {
        let total: usize = counts.iter().sum();
        if total > 0 {
            println!("run of {len:>2} frames >= 0.65: {total:>5} runs; labelled changes inside 0/1/2/3/4+: {counts:?}");
        }
    }
    for (g, &(n, m, lm, hi)) in fast.iter().enumerate().skip(1) {
        println!("gap {g} frames: {n} changes, missed {m}: sub-threshold local max {lm}, at >= 0.65 without own peak {hi}");
    }
    for (e, label) in [(0, "works"), (1, "études")] {
        println!("{label}: misses by time since the previous labelled change");
        for (b, &(n, m)) in by_gap[e].iter().enumerate() {
            println!(
                "  {:>4.2}–{:>4.2} s: {n:>5} changes, missed {m:>4} ({:.3})",
                bins[b],
                bins[b + 1],
                m as f64 / n.max(1) as f64
            );
        }
        let (s, o, x) = false_kind[e];
        println!(
            "  false changes: on a slurred note change {s} (of {} slurred), on another onset {o}, elsewhere {x}",
            slurred_total[e]
        );
    }
    Ok(())
}
