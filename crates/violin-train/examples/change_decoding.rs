//! Two ways of decoding the shipped ensemble's bow changes that might help violins the
//! network never heard, measured on the validation items of a corpus (training violins) and
//! of the same items rendered with another violin (`corpus … --validation-violin`):
//! bow-change F1 at ±2 frames, events pooled. No test item is read.
//!
//! * **Per-recording threshold** (default). On a violin it never heard, the ensemble's
//!   change probabilities are lower and its misses outnumber its false changes (held-out
//!   violins: precision 0.91, recall 0.76). With `L` the `q`-quantile of the heights of a
//!   recording's local maxima at or above 0.2, its threshold is `min(threshold, r·L)`.
//! * **Ensemble weight** (`--mix`): the change probability `w·stroke + (1 − w)·CNN` instead
//!   of the mean, for `w` in 0.2–0.8, each with its best threshold and spacing.
//!
//! `cargo run --release -p violin-train --example change_decoding -- CORPUS VAL_VIOLIN_CORPUS [--mix]`

use std::path::{Path, PathBuf};

use bowing_net::data::Recording;
use bowing_net::metrics::{match_events, Counts};
use bowing_net::{BowingModel, Decoder};
use violin_train::bowing_data::load_dataset;

type Error = Box<dyn std::error::Error>;

/// The stroke network's and the CNN's change probabilities of every recording.
type Members = Vec<(Vec<f32>, Vec<f32>)>;

fn validation_items(dir: &Path) -> Result<Vec<Recording>, Error> {
    Ok(load_dataset(dir, &|_, _| {})?.val)
}

fn members(recs: &[Recording]) -> Result<Members, Error> {
    let cnn = BowingModel::pretrained_ensemble_cnn()?;
    let net = BowingModel::pretrained_strokes()?;
    recs.iter()
        .map(|r| {
            let stroke = net.frame_outputs(r.mel_db.view())?.change;
            Ok((stroke, cnn.frame_probabilities(r.mel_db.view())?))
        })
        .collect()
}

/// `w·stroke + (1 − w)·CNN` of every recording (`w` = 0.5: the shipped ensemble).
fn mixed(m: &Members, w: f32) -> Vec<Vec<f32>> {
    m.iter()
        .map(|(s, c)| {
            s.iter()
                .zip(c)
                .map(|(s, c)| w * s + (1.0 - w) * c)
                .collect()
        })
        .collect()
}

/// The `q`-quantile of the heights of the local maxima of `p` at or above 0.2 (1 when
/// there are none, so the threshold is left alone).
fn peak_level(p: &[f32], q: f64) -> f32 {
    // The decoder's own local maxima (spacing 1: none suppressed).
    let all_peaks = Decoder {
        threshold: 0.2,
        min_spacing_frames: 1,
        run_split: None,
    };
    let mut peaks: Vec<f32> = all_peaks.pick(p).into_iter().map(|i| p[i]).collect();
    if peaks.is_empty() {
        return 1.0;
    }
    peaks.sort_by(f32::total_cmp);
    peaks[((peaks.len() - 1) as f64 * q).round() as usize]
}

/// A decoder with its per-recording threshold factor (`r` = ∞: the plain decoder).
#[derive(Clone, Copy)]
struct Choice {
    decoder: Decoder,
    r: f32,
    q: f64,
}

/// Pooled counts of `choice` over `probs` of `recs`.
fn counts(probs: &[Vec<f32>], recs: &[Recording], c: Choice) -> Counts {
    let mut total = Counts::default();
    for (p, rec) in probs.iter().zip(recs) {
        let threshold = c.decoder.threshold.min(c.r * peak_level(p, c.q));
        let own = Decoder {
            threshold,
            ..c.decoder
        };
        total.add(&match_events(&own.pick(p), &rec.changes, 2));
    }
    total
}

fn prf(c: &Counts) -> String {
    format!("{:.3}/{:.3}/{:.3}", c.precision(), c.recall(), c.f1())
}

/// The validation sets and their members' probabilities.
struct Sets {
    heard: Vec<Recording>,
    unheard: Vec<Recording>,
    mh: Members,
    mu: Members,
}

impl Sets {
    /// Pooled F1 over both sets and a table row, for ensemble weight `w`.
    fn row(&self, w: f32, c: Choice) -> (f64, String) {
        let (p, q) = (mixed(&self.mh, w), mixed(&self.mu, w));
        let (a, b) = (counts(&p, &self.heard, c), counts(&q, &self.unheard, c));
        let mut both = a;
        both.add(&b);
        let f = both.f1();
        let line = format!(
            "| {w} | {} | {} | {} | {} | {} | {} | {f:.3} |",
            c.decoder.threshold,
            c.decoder.min_spacing_frames,
            c.r,
            c.q,
            prf(&a),
            prf(&b)
        );
        (f, line)
    }
}

/// Every plain decoder of the grid (threshold 0.30–0.80, spacing 2–4).
fn decoders() -> impl Iterator<Item = Decoder> {
    (2..=4).flat_map(|spacing| {
        (6..=16).map(move |k| Decoder {
            threshold: 0.05 * k as f32,
            min_spacing_frames: spacing,
            run_split: None,
        })
    })
}

fn main() -> Result<(), Error> {
    let all: Vec<String> = std::env::args().skip(1).collect();
    let mix = all.iter().any(|a| a == "--mix");
    let paths: Vec<PathBuf> = all
        .iter()
        .filter(|a| !a.starts_with("--"))
        .map(PathBuf::from)
        .collect();
    let [corpus, other] = paths.as_slice() else {
        return Err("usage: change_decoding CORPUS VAL_VIOLIN_CORPUS [--mix]".into());
    };
    let (heard, unheard) = (validation_items(corpus)?, validation_items(other)?);
    let sets = Sets {
        mh: members(&heard)?,
        mu: members(&unheard)?,
        heard,
        unheard,
    };
    let shipped = Choice {
        decoder: BowingModel::pretrained_strokes()?
            .ensemble_decoder()
            .ok_or("the shipped stroke network has no ensemble decoder")?,
        r: f32::INFINITY,
        q: 0.5,
    };
    println!("| w | threshold | spacing | r | q | training violins P/R/F1 | unheard violin P/R/F1 | both F1 |");
    println!("|---|---|---|---|---|---|---|---|");
    let (base, line) = sets.row(0.5, shipped);
    println!("{line} (shipped)");
    let weights: &[f32] = if mix {
        &[0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8]
    } else {
        &[0.5]
    };
    let factors: &[(f32, f64)] = if mix {
        &[(f32::INFINITY, 0.5)]
    } else {
        &[
            (0.5, 0.5),
            (0.6, 0.5),
            (0.7, 0.5),
            (0.8, 0.5),
            (0.9, 0.5),
            (0.5, 0.75),
            (0.6, 0.75),
            (0.7, 0.75),
            (0.8, 0.75),
            (0.9, 0.75),
            (0.5, 0.9),
            (0.6, 0.9),
            (0.7, 0.9),
            (0.8, 0.9),
            (0.9, 0.9),
        ]
    };
    for &w in weights {
        let mut best = (f64::NEG_INFINITY, String::new());
        for decoder in decoders() {
            for &(r, q) in factors {
                let (f, line) = sets.row(w, Choice { decoder, r, q });
                if f > best.0 {
                    best = (f, line);
                }
            }
        }
        println!("{}", best.1);
        eprintln!("w {w}: best {:.3} against the shipped {base:.3}", best.0);
    }
    Ok(())
}
