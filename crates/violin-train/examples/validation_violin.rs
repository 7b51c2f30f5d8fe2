//! Bow-change decoding checked on a violin training never hears: the validation items of a
//! corpus (training violins) and the same items rendered with another violin (`violin-skeleton
//! corpus … --validation-violin V.pat`), scored apart and together, for each stroke-network
//! weights file given — the network alone with its own decoder, and the shipped ensemble
//! (its mean with the CNN) with the file's stored ensemble decoder and with a decoder
//! re-tuned on both validation sets (bow-change F1 at ±2 frames, events pooled).
//!
//! With `--write`, the first weights file's ensemble decoder is replaced by the re-tuned one
//! when that gains at least 0.005 F1 on all sets pooled (the rule `train_strokes` applies
//! to a stored decoder). No test item is read.
//!
//! With `--timbre-averaging K:DEPTH_DB:SEED`, the stroke network's change probability is the
//! mean over its input and K copies heard through random equalisers
//! (`bowing_net::stroke::timbre`, at most DEPTH_DB deep, curves drawn from SEED): test-time
//! averaging over the timbres training augmented with.
//!
//! With `--partner P.safetensors`, the ensemble's other member is the stroke network `P`
//! instead of the CNN (two stroke networks averaged: an experiment, not a shipped model, so
//! `--write` is refused with it).
//!
//! With `--cnn C.safetensors`, the ensemble's CNN is `C` instead of the shipped one; with
//! `--write` too, the re-tuned decoder is stored whatever its gain (the stored one was tuned
//! for another CNN), to be shipped with `C`.
//!
//! Several validation-violin corpora may be given (folders; weights are files): each is
//! scored on its own, all are pooled, and the mean of the sets' F1s is printed too; the
//! re-tuned decoder is tuned on all of them pooled.
//!
//! `cargo run --release -p violin-train --example validation_violin -- CORPUS VAL_VIOLIN_CORPUS [VAL_VIOLIN_CORPUS2 …] W.safetensors [W2 …] [--write] [--timbre-averaging K:DEPTH_DB:SEED] [--partner P.safetensors] [--cnn C.safetensors] [--run-split | --write-run-split | --write-alone-run-split]`
//!
//! With `--run-split`, the network's own decoder and the stored ensemble decoder are also
//! scored with the [`bowing_net::RunSplit`] tuned on all sets pooled (their threshold and
//! spacing kept); `--write-run-split` (ensemble) and `--write-alone-run-split` (the network
//! alone) store that decoder in the first weights file, whatever its gain (the caller's rule
//! decides whether the file is kept).

use std::path::{Path, PathBuf};

use bowing_net::data::Recording;
use bowing_net::metrics::{decoder_f1, tune_decoder, tune_run_split};
use bowing_net::stroke::{timbre, StrokeDetector};
use bowing_net::{BowChangeDetector, Decoder};
use violin_train::bowing_data::load_dataset;
use violin_train::example_args::flag_value;

/// The validation F1 a re-tuned decoder must gain to replace a stored one.
const MIN_DECODER_GAIN_F1: f64 = 0.005;

fn validation_items(dir: &Path) -> Result<Vec<Recording>, Box<dyn std::error::Error>> {
    Ok(load_dataset(dir, &|_, _| {})?.val)
}

type Probs = Vec<Vec<f32>>;

/// Test-time timbre averaging: copies, depth (dB), seed.
type Averaging = Option<(usize, f32, u64)>;

fn parse_averaging(args: &[String]) -> Result<Averaging, Box<dyn std::error::Error>> {
    let Some(spec) = flag_value(args, "--timbre-averaging")? else {
        return Ok(None);
    };
    let parts: Vec<&str> = spec.split(':').collect();
    let [k, depth, seed] = parts.as_slice() else {
        return Err(format!("--timbre-averaging {spec}: expected K:DEPTH_DB:SEED").into());
    };
    Ok(Some((k.parse()?, depth.parse()?, seed.parse()?)))
}

/// The stroke network's change probability of `mel`, averaged over timbres when asked.
fn stroke_changes(
    net: &StrokeDetector,
    mel: ndarray::ArrayView2<f32>,
    averaging: Averaging,
) -> Result<Vec<f32>, Box<dyn std::error::Error>> {
    let mut change = net.frame_outputs(mel)?.change;
    let Some((copies, depth_db, seed)) = averaging else {
        return Ok(change);
    };
    let input = bowing_net::stroke::stroke_input(mel);
    let features = input.ncols();
    let mut rng = net_core::rng::Rng::new(seed);
    for _ in 0..copies {
        let curve = net_core::frames::random_eq_curve(&mut rng, features - 2, depth_db);
        let mut copy = input.clone();
        let flat = copy.as_slice_mut().ok_or("input not contiguous")?;
        timbre::equalise(flat, features, &curve);
        let other = net.net().frame_outputs(&copy)?.change;
        for (c, o) in change.iter_mut().zip(&other) {
            *c += o;
        }
    }
    let n = (copies + 1) as f32;
    change.iter_mut().for_each(|c| *c /= n);
    Ok(change)
}

/// The ensemble's other member: the shipped CNN or a second stroke network.
enum Partner {
    Cnn(BowChangeDetector),
    Strokes(StrokeDetector),
}

impl Partner {
    fn changes(
        &self,
        mel: ndarray::ArrayView2<f32>,
    ) -> Result<Vec<f32>, Box<dyn std::error::Error>> {
        Ok(match self {
            Partner::Cnn(cnn) => cnn.frame_probabilities(mel)?,
            Partner::Strokes(net) => net.frame_outputs(mel)?.change,
        })
    }
}

/// (network alone, ensemble) change probabilities of every recording.
fn probabilities(
    partner: &Partner,
    net: &StrokeDetector,
    recs: &[Recording],
    averaging: Averaging,
) -> Result<(Probs, Probs), Box<dyn std::error::Error>> {
    let mut alone = Vec::with_capacity(recs.len());
    let mut ensemble = Vec::with_capacity(recs.len());
    for r in recs {
        let a = partner.changes(r.mel_db.view())?;
        let b = stroke_changes(net, r.mel_db.view(), averaging)?;
        let mut mean = b.clone();
        bowing_net::stroke::average_changes(&mut mean, &a);
        ensemble.push(mean);
        alone.push(b);
    }
    Ok((alone, ensemble))
}

/// F1 of decoder `d` on the training violins' items, on each unheard violin's, and on all
/// of them pooled; `p[0]` belongs to `sets[0]` (the training violins), and so on.
fn f1s(d: &Decoder, p: &[(Probs, Probs)], sets: &[Vec<Recording>], ensemble: bool) -> Vec<f64> {
    let pick = |x: &(Probs, Probs)| if ensemble { x.1.clone() } else { x.0.clone() };
    let mut out: Vec<f64> = p
        .iter()
        .zip(sets)
        .map(|(x, recs)| decoder_f1(&pick(x), recs, d))
        .collect();
    let all_p: Probs = p.iter().flat_map(pick).collect();
    let all_r: Vec<Recording> = sets.iter().flatten().cloned().collect();
    out.push(decoder_f1(&all_p, &all_r, d));
    out
}

/// The path after `flag`, if the flag is given.
fn flag_path(args: &[String], flag: &str) -> Result<Option<PathBuf>, String> {
    Ok(flag_value(args, flag)?.map(PathBuf::from))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: validation_violin CORPUS VAL_VIOLIN_CORPUS [VAL_VIOLIN_CORPUS2 …] W.safetensors [W2 …] [--write] [--timbre-averaging K:DEPTH_DB:SEED] [--partner P.safetensors] [--cnn C.safetensors] [--run-split | --write-run-split | --write-alone-run-split]";
    let write = args.iter().any(|a| a == "--write");
    let write_run_split = args.iter().any(|a| a == "--write-run-split");
    let write_alone_run_split = args.iter().any(|a| a == "--write-alone-run-split");
    let run_split =
        write_run_split || write_alone_run_split || args.iter().any(|a| a == "--run-split");
    if write && write_run_split {
        return Err("--write and --write-run-split each store a decoder: give one".into());
    }
    let averaging = parse_averaging(&args)?;
    let paths: Vec<PathBuf> = args
        .iter()
        .enumerate()
        .filter(|(i, a)| {
            !a.starts_with("--")
                && (*i == 0
                    || !["--timbre-averaging", "--partner", "--cnn"]
                        .contains(&args[i - 1].as_str()))
        })
        .map(|(_, a)| a)
        .map(PathBuf::from)
        .collect();
    // Corpora are folders, weights files: CORPUS, then one or more validation-violin corpora.
    let (corpora, weights): (Vec<PathBuf>, Vec<PathBuf>) =
        paths.into_iter().partition(|p| p.is_dir());
    if corpora.len() < 2 || weights.is_empty() {
        return Err(usage.into());
    }
    let mut sets = Vec::with_capacity(corpora.len());
    for dir in &corpora {
        let items = validation_items(dir)?;
        eprintln!("{}: {} validation items", dir.display(), items.len());
        sets.push(items);
    }
    let partner_path = flag_path(&args, "--partner")?;
    let cnn_path = flag_path(&args, "--cnn")?;
    if (write || write_run_split) && partner_path.is_some() {
        return Err(
            "--write and --write-run-split store the CNN ensemble's decoder; they cannot be used with --partner".into(),
        );
    }
    let partner = match &partner_path {
        Some(p) => Partner::Strokes(StrokeDetector::load(p)?),
        None => match &cnn_path {
            Some(p) => Partner::Cnn(BowChangeDetector::load(p)?),
            None => Partner::Cnn(bowing_net::BowingModel::pretrained_ensemble_cnn()?),
        },
    };
    let names: Vec<String> = corpora[1..]
        .iter()
        .map(|c| {
            c.file_name()
                .map_or_else(|| c.display().to_string(), |n| n.to_string_lossy().into())
        })
        .collect();
    println!(
        "| weights | decoder | training violins | {} | all pooled | mean of sets |",
        names.join(" | ")
    );
    println!("|---|---|---|{}---|---|", "---|".repeat(names.len()));
    for (k, w) in weights.iter().enumerate() {
        let mut net = StrokeDetector::load(w)?;
        let p = sets
            .iter()
            .map(|recs| probabilities(&partner, &net, recs, averaging))
            .collect::<Result<Vec<_>, _>>()?;
        let row = |what: String, f: Vec<f64>| {
            let per_set = &f[..f.len() - 1];
            let mean = per_set.iter().sum::<f64>() / per_set.len() as f64;
            let cells: Vec<String> = f.iter().map(|v| format!("{v:.4}")).collect();
            println!(
                "| {} | {what} | {} | {mean:.4} |",
                w.display(),
                cells.join(" | ")
            );
        };
        let own = net.decoder();
        row(
            format!("network alone, {own:?}"),
            f1s(&own, &p, &sets, false),
        );
        let all_r: Vec<Recording> = sets.iter().flatten().cloned().collect();
        if run_split {
            let alone_p: Probs = p.iter().flat_map(|x| x.0.clone()).collect();
            let (split, _) = tune_run_split(&alone_p, &all_r, own);
            row(
                format!("network alone + run split tuned on all sets {split:?}"),
                f1s(&split, &p, &sets, false),
            );
            if write_alone_run_split && k == 0 {
                net.set_decoder(split);
                net.save(w)?;
                eprintln!("{}: network decoder {split:?} written", w.display());
            }
        }
        let all_p: Probs = p.iter().flat_map(|x| x.1.clone()).collect();
        let (tuned, tuned_f1) = tune_decoder(&all_p, &all_r);
        let stored = match partner {
            Partner::Cnn(_) => net.ensemble_decoder(),
            Partner::Strokes(_) => None,
        };
        if let Some(s) = stored {
            row(format!("ensemble, stored {s:?}"), f1s(&s, &p, &sets, true));
            if run_split {
                let (split, _) = tune_run_split(&all_p, &all_r, s);
                row(
                    format!("ensemble, stored + run split tuned on all sets {split:?}"),
                    f1s(&split, &p, &sets, true),
                );
                if write_run_split && k == 0 {
                    net.set_ensemble_decoder(Some(split));
                    net.save(w)?;
                    eprintln!("{}: ensemble decoder {split:?} written", w.display());
                }
            }
        }
        row(
            format!("ensemble, re-tuned on all sets {tuned:?}"),
            f1s(&tuned, &p, &sets, true),
        );
        if write && k == 0 {
            let stored_f1 = stored.map_or(f64::NEG_INFINITY, |s| decoder_f1(&all_p, &all_r, &s));
            // A stored decoder was tuned for the shipped CNN; with another CNN it is
            // replaced whatever the gain (the two are shipped together).
            let min_gain = if cnn_path.is_some() {
                f64::NEG_INFINITY
            } else {
                MIN_DECODER_GAIN_F1
            };
            if tuned_f1 >= stored_f1 + min_gain {
                net.set_ensemble_decoder(Some(tuned));
                net.save(w)?;
                eprintln!(
                    "{}: ensemble decoder {tuned:?} written ({tuned_f1:.3} against {stored_f1:.3})",
                    w.display()
                );
            } else {
                eprintln!(
                    "{}: stored decoder kept ({stored_f1:.3}; re-tuned {tuned_f1:.3})",
                    w.display()
                );
            }
        }
    }
    Ok(())
}
