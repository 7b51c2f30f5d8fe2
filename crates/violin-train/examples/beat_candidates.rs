//! Every reading the bar-pointer decoder could give of a corpus item, with what it would
//! score — the data for fitting how the metre and the beat level are chosen
//! (`scripts/bar_choice_ceiling.py`). Only the **training and validation** splits are read.
//!
//! Per item (one JSON line): its split, whether it is an étude, the labelled bar length and
//! the played tempo at the notated beat; per candidate reading — each bar length decoded on
//! its own, and from the 2- and 4-beat paths every other beat (half the tempo), from the 1-
//! and 2-beat paths a beat between each two (twice the tempo) — its features (from the
//! activations only) and its beat F, downbeat F, metre and tempo correctness.
//!
//! `cargo run --release -p violin-train --example beat_candidates -- CORPUS OUT.jsonl`

use std::io::Write;
use std::path::PathBuf;

use beat_net::BeatActivation;
use beat_track::bar_pointer::{decode, BarPointerBeats, BarPointerConfig};
use beat_track::eval::{beat_prf, trim_beats};
use corpus::manifest::Split;
use rayon::prelude::*;
use serde_json::json;
use violin_train::beat_data::read_first_column;
use violin_train::bowing_data::read_manifest;
use violin_train::feature_cache::cached_mel30;

const FPS: f64 = 30.0;

/// Largest value of `v` within a frame of time `t_s`.
fn at(v: &[f32], t_s: f64) -> f64 {
    let f = (t_s * FPS).round().max(0.0) as usize;
    let lo = f.saturating_sub(1).min(v.len());
    let hi = (f + 2).min(v.len());
    v[lo..hi].iter().copied().fold(0.0f32, f32::max) as f64
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 {
        0.0
    } else {
        s / n as f64
    }
}

/// A reading: beats, downbeats and beats per bar.
struct Reading {
    kind: &'static str,
    beats: Vec<f64>,
    downbeats: Vec<f64>,
    bar: usize,
    log_p: f64,
}

fn tempo_of(beats: &[f64]) -> f64 {
    let mut d: Vec<f64> = beats.windows(2).map(|w| w[1] - w[0]).collect();
    d.sort_by(f64::total_cmp);
    d.get(d.len() / 2).map_or(0.0, |m| 60.0 / m.max(1e-6))
}

fn readings(out: &BarPointerBeats, log_p: f64) -> Vec<Reading> {
    let b = out.beats_per_bar;
    let mut v = vec![Reading {
        kind: "decoded",
        beats: out.beats_s.clone(),
        downbeats: out.downbeats_s.clone(),
        bar: b,
        log_p,
    }];
    if b.is_multiple_of(2) {
        // Half tempo: keep the beats an even number of beats after a downbeat.
        let mut beats = Vec::new();
        let mut index = 0usize;
        for &t in &out.beats_s {
            if out.downbeats_s.iter().any(|d| (d - t).abs() < 1e-6) {
                index = 0;
            }
            if index.is_multiple_of(2) {
                beats.push(t);
            }
            index += 1;
        }
        v.push(Reading {
            kind: "half",
            beats,
            downbeats: out.downbeats_s.clone(),
            bar: b / 2,
            log_p,
        });
    }
    if b <= 2 {
        let mut beats = Vec::new();
        for w in out.beats_s.windows(2) {
            beats.push(w[0]);
            if w[1] - w[0] < 2.0 {
                beats.push(0.5 * (w[0] + w[1]));
            }
        }
        beats.extend(out.beats_s.last());
        v.push(Reading {
            kind: "double",
            beats,
            downbeats: out.downbeats_s.clone(),
            bar: 2 * b,
            log_p,
        });
    }
    v
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: beat_candidates CORPUS OUT.jsonl";
    let dir: PathBuf = args.first().ok_or(usage)?.into();
    let out_path: PathBuf = args.get(1).ok_or(usage)?.into();
    let net = BeatActivation::pretrained()?;
    let base = BarPointerConfig::default();
    let manifest = read_manifest(&dir)?;
    let items: Vec<_> = manifest
        .items
        .iter()
        .filter(|it| matches!(it.split, Split::Train | Split::Val))
        .collect();
    let lines: Vec<String> = items
        .par_iter()
        .map(|it| -> Result<String, String> {
            let d = dir.join(&it.dir);
            let err = |e: &dyn std::fmt::Display| format!("{}: {e}", it.dir);
            let mel = cached_mel30(&d, &corpus::layout::item_audio(&d)).map_err(|e| err(&e))?;
            let act = net.activations(mel.view()).map_err(|e| err(&e))?;
            let beats = read_first_column(&d.join("beats.txt")).map_err(|e| err(&e))?;
            let downbeats = read_first_column(&d.join("downbeats.txt")).map_err(|e| err(&e))?;
            let (bar, tempo) = violin_train::beat_data::notated_meter(&d);
            let tempo = tempo.unwrap_or(f64::NAN);
            let any: Vec<f32> = act.any_beat();
            let frames = act.beat.len() as f64 * base.upsample as f64;
            let tr = |v: &[f64]| trim_beats(v, 5.0);
            let mut cands = Vec::new();
            for (k, &n) in base.beats_per_bar.iter().enumerate() {
                let cfg = BarPointerConfig {
                    beats_per_bar: vec![n],
                    bar_length_prior_per_frame: vec![],
                    ..base.clone()
                };
                let out = decode(&act.beat, &act.downbeat, &cfg).map_err(|e| err(&e))?;
                let log_p = out.log_probability.first().copied().unwrap_or(f64::NAN);
                for r in readings(&out, log_p) {
                    let mids: Vec<f64> = r
                        .beats
                        .windows(2)
                        .filter(|w| w[1] - w[0] < 2.0)
                        .map(|w| 0.5 * (w[0] + w[1]))
                        .collect();
                    let thirds: Vec<f64> = r
                        .beats
                        .windows(2)
                        .filter(|w| w[1] - w[0] < 2.0)
                        .flat_map(|w| {
                            [(2.0 * w[0] + w[1]) / 3.0, (w[0] + 2.0 * w[1]) / 3.0]
                        })
                        .collect();
                    let is_down = |t: f64| r.downbeats.iter().any(|d| (d - t).abs() < 1e-6);
                    let t = tempo_of(&r.beats);
                    cands.push(json!({
                        "beats_s": r.beats, "downbeats_s": r.downbeats,
                        "bar": r.bar, "kind": r.kind, "path_bar": n, "prior_index": k,
                        "log_p_per_frame": r.log_p / frames,
                        "tempo_bpm": t,
                        "beats": r.beats.len(),
                        "act_beats": mean(r.beats.iter().map(|&b| at(&any, b))),
                        "act_mids": mean(mids.iter().map(|&b| at(&any, b))),
                        "act_thirds": mean(thirds.iter().map(|&b| at(&any, b))),
                        "down_at_down": mean(r.downbeats.iter().map(|&b| at(&act.downbeat, b))),
                        "down_at_other": mean(r.beats.iter().filter(|&&b| !is_down(b)).map(|&b| at(&act.downbeat, b))),
                        "beat_f": beat_prf(&tr(&beats), &tr(&r.beats), 0.07).f_measure,
                        "downbeat_f": beat_prf(&tr(&downbeats), &tr(&r.downbeats), 0.07).f_measure,
                        "metre_ok": bar.is_some_and(|b| usize::from(b) == r.bar),
                        "tempo_ok": (t / tempo - 1.0).abs() <= 0.08,
                    }));
                }
            }
            Ok(json!({
                "item": it.dir, "split": format!("{:?}", it.split), "etude": it.is_etude(),
                "meter": it.meter, "bar": bar, "tempo_bpm": tempo,
                "duration_s": it.duration_s, "candidates": cands,
            })
            .to_string())
        })
        .collect::<Result<_, _>>()?;
    let mut f = std::io::BufWriter::new(std::fs::File::create(&out_path)?);
    for l in &lines {
        writeln!(f, "{l}")?;
    }
    eprintln!("{} items → {}", lines.len(), out_path.display());
    Ok(())
}
