//! Where the beat tracker goes wrong, on a corpus's **training or validation** split (the
//! test sets are refused): beat-net's activations decoded by the default bar-pointer
//! decoder, per item and summed up for études and works apart —
//!
//! * beat F, downbeat F (±70 ms, first 5 s ignored), metre and tempo (±8 %) accuracy;
//! * the tempo errors by their ratio to the played tempo at the notated beat (×2, ×½, ×3,
//!   ×⅓, ×3/2, ×2/3), and for each kind the median number of notes per beat at the
//!   notated and at the decoded tempo;
//! * the bar lengths decoded for each labelled bar length (a confusion table);
//! * beat-net's downbeat probability at each labelled beat of the bar (its largest value
//!   within a frame of the beat), averaged per labelled bar length: how far the network
//!   tells a bar's first beat from the others.
//!
//! `cargo run --release -p violin-train --example beat_errors -- CORPUS [train|val] [--items]`

use std::collections::BTreeMap;
use std::path::PathBuf;

use beat_net::BeatActivation;
use beat_track::bar_pointer::{decode, BarPointerConfig};
use beat_track::eval::{beat_prf, trim_beats};
use corpus::manifest::Split;
use violin_train::beat_data::read_first_column;
use violin_train::bowing_data::read_manifest;
use violin_train::feature_cache::cached_mel30;

/// Tempo ratios named in the summary (estimated / notated).
const RATIOS: [(&str, f64); 7] = [
    ("right", 1.0),
    ("×2", 2.0),
    ("×½", 0.5),
    ("×3", 3.0),
    ("×⅓", 1.0 / 3.0),
    ("×3/2", 1.5),
    ("×2/3", 2.0 / 3.0),
];

#[derive(Default)]
struct Summary {
    items: usize,
    beat_f: f64,
    downbeat_f: f64,
    metre: usize,
    tempo: BTreeMap<&'static str, usize>,
    /// Per tempo kind, notes per beat at the notated and at the decoded tempo.
    notes_per_beat: BTreeMap<&'static str, (Vec<f64>, Vec<f64>)>,
    /// (labelled, decoded) bar lengths → items.
    confusion: BTreeMap<(u64, usize), usize>,
    /// labelled bar length → per beat of the bar (sum, count) of the downbeat probability.
    profile: BTreeMap<u64, Vec<(f64, usize)>>,
}

fn tempo_kind(estimated: f64, notated: f64) -> &'static str {
    RATIOS
        .iter()
        .find(|(_, r)| (estimated / (notated * r) - 1.0).abs() <= 0.08)
        .map_or("other", |(name, _)| name)
}

/// Per labelled beat, its index in the bar and beat-net's downbeat probability there.
fn beat_profile(beats: &[f64], downbeats: &[f64], downbeat_act: &[f32]) -> Vec<(usize, f64)> {
    let mut out = Vec::new();
    for &b in beats {
        let Some(&bar_start) = downbeats.iter().rev().find(|&&d| d <= b + 0.01) else {
            continue;
        };
        let index = beats
            .iter()
            .filter(|&&x| x >= bar_start - 0.01 && x < b - 0.01)
            .count();
        let f = (b * 30.0).round() as usize;
        let lo = f.saturating_sub(1).min(downbeat_act.len());
        let hi = (f + 2).min(downbeat_act.len());
        if let Some(p) = downbeat_act[lo..hi].iter().copied().reduce(f32::max) {
            out.push((index, f64::from(p)));
        }
    }
    out
}

fn median(v: &[f64]) -> f64 {
    let mut v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: beat_errors CORPUS [train|val] [--items]";
    let dir: PathBuf = args.first().ok_or(usage)?.into();
    let split = match args.get(1).map(String::as_str) {
        None | Some("val") | Some("--items") => Split::Val,
        Some("train") => Split::Train,
        Some(other) => return Err(format!("{other}: give train or val ({usage})").into()),
    };
    let per_item = args.iter().any(|a| a == "--items");
    let net = BeatActivation::pretrained()?;
    let cfg = BarPointerConfig::default();
    let manifest = read_manifest(&dir)?;
    let mut summaries: BTreeMap<&str, Summary> = BTreeMap::new();
    for it in manifest.items.iter().filter(|it| it.split == split) {
        let d = dir.join(&it.dir);
        let mel = cached_mel30(&d, &corpus::layout::item_audio(&d))?;
        let labels: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.join("labels.json"))?)?;
        let act = net.activations(mel.view())?;
        let beats = read_first_column(&d.join("beats.txt"))?;
        let downbeats = read_first_column(&d.join("downbeats.txt"))?;
        let out = decode(&act.beat, &act.downbeat, &cfg)?;
        let tr = |v: &[f64]| trim_beats(v, 5.0);
        let beat_f = beat_prf(&tr(&beats), &tr(&out.beats_s), 0.07).f_measure;
        let downbeat_f = beat_prf(&tr(&downbeats), &tr(&out.downbeats_s), 0.07).f_measure;
        let bar = labels["beats_per_bar"].as_u64().unwrap_or(0);
        let notated = violin_train::beat_data::notated_meter(&d)
            .1
            .unwrap_or(f64::NAN);
        let kind = tempo_kind(out.tempo_bpm, notated);
        let s = summaries
            .entry(if it.is_etude() { "études" } else { "works" })
            .or_default();
        s.items += 1;
        s.beat_f += beat_f;
        s.downbeat_f += downbeat_f;
        s.metre += usize::from(bar == out.beats_per_bar as u64);
        *s.tempo.entry(kind).or_default() += 1;
        let notes_per_min = it.notes as f64 / it.duration_s.max(1e-9) * 60.0;
        let npb = s.notes_per_beat.entry(kind).or_default();
        npb.0.push(notes_per_min / notated);
        npb.1.push(notes_per_min / out.tempo_bpm.max(1e-9));
        *s.confusion.entry((bar, out.beats_per_bar)).or_default() += 1;
        let profile = s.profile.entry(bar).or_default();
        for (index, p) in beat_profile(&beats, &downbeats, &act.downbeat) {
            if profile.len() <= index {
                profile.resize(index + 1, (0.0, 0));
            }
            profile[index].0 += p;
            profile[index].1 += 1;
        }
        if per_item {
            println!(
                "{}\t{}\t{}\tbar {bar} → {}\ttempo {notated:.0} → {:.0} ({kind})\tbeat F {beat_f:.3}\tdownbeat F {downbeat_f:.3}",
                it.dir, it.work, it.meter, out.beats_per_bar, out.tempo_bpm
            );
        }
    }
    for (music, s) in &summaries {
        let n = s.items.max(1) as f64;
        println!(
            "\n## {music}: {} items — beat F {:.3}, downbeat F {:.3}, metre {:.3}",
            s.items,
            s.beat_f / n,
            s.downbeat_f / n,
            s.metre as f64 / n
        );
        let tempo: Vec<String> = s
            .tempo
            .iter()
            .map(|(k, v)| format!("{k} {:.3}", *v as f64 / n))
            .collect();
        println!("tempo: {}", tempo.join(", "));
        for (kind, (at_notated, at_decoded)) in &s.notes_per_beat {
            println!(
                "  {kind}: median notes per beat {:.2} at the notated tempo, {:.2} at the decoded",
                median(at_notated),
                median(at_decoded)
            );
        }
        println!("bar lengths, labelled → decoded (items):");
        for ((bar, decoded), count) in &s.confusion {
            println!("  {bar} → {decoded}: {count}");
        }
        println!("downbeat probability at each labelled beat of the bar:");
        for (bar, profile) in &s.profile {
            let p: Vec<String> = profile
                .iter()
                .map(|(sum, count)| format!("{:.2}", sum / (*count).max(1) as f64))
                .collect();
            println!("  {bar} beats: {}", p.join(" "));
        }
    }
    Ok(())
}
