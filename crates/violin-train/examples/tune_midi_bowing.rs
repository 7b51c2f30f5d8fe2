//! Chooses the MIDI bowing rules ([`performance::midi::MidiBowing`]) on a corpus's
//! **validation** split: every item's score as a MIDI file would give it
//! ([`violin_train::item_score`]) is bowed by each rule set of a grid, and its bow changes
//! are scored against the labelled ones (F, ±100 ms, changes in the first 0.1 s ignored,
//! counts pooled over the items), with the share of labelled strokes whose direction comes
//! out right. Prints the default rules' figures, the best rule sets, and the same figures on
//! the training split for the best one. The test sets are never read.
//!
//! `cargo run --release -p violin-train --example tune_midi_bowing -- CORPUS`

use std::path::PathBuf;

use corpus::manifest::Split;
use performance::midi::{
    separated_share, timeline_from_score_with, timing_is_notated, MidiBowing, MidiScore,
};
use performance::{bow_directions, match_events, strokes_of, BowStroke, Note};
use rayon::prelude::*;
use violin_train::beat_data::read_first_column;
use violin_train::bowing_data::{read_manifest, read_strokes};
use violin_train::evaluate::direction_tally;
use violin_train::item_score::item_midi_score;

struct Item {
    score: MidiScore,
    changes_s: Vec<f64>,
    strokes: Vec<BowStroke>,
}

/// (matched, labelled, found, directions right, strokes) over `items` bowed by `rules`.
fn measure(items: &[Item], rules: &MidiBowing) -> (usize, usize, usize, usize, usize) {
    items
        .par_iter()
        .map(|it| {
            let timeline = timeline_from_score_with(&it.score, rules);
            let changes = timeline.bow_changes_s();
            let notes: Vec<Note> = timeline.notes.iter().map(|n| n.note).collect();
            let directions = bow_directions(&changes, &notes, &it.score.downbeats_s);
            let strokes = strokes_of(&changes, &directions, &notes);
            let found: Vec<f64> = changes.iter().copied().filter(|t| *t >= 0.1).collect();
            let matched = match_events(&it.changes_s, &found, 0.1).len();
            let d = direction_tally(&it.strokes, &strokes);
            (matched, it.changes_s.len(), found.len(), d.right, d.total)
        })
        .reduce(
            || (0, 0, 0, 0, 0),
            |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2, a.3 + b.3, a.4 + b.4),
        )
}

fn line(name: &str, m: (usize, usize, usize, usize, usize)) -> String {
    let p = m.0 as f64 / m.2.max(1) as f64;
    let r = m.0 as f64 / m.1.max(1) as f64;
    format!(
        "{name}: bow-change F {:.3} (P {p:.3}, R {r:.3}), direction {:.3}",
        performance::f_measure(p, r),
        m.3 as f64 / m.4.max(1) as f64
    )
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir: PathBuf = std::env::args()
        .nth(1)
        .ok_or("usage: tune_midi_bowing CORPUS")?
        .into();
    let manifest = read_manifest(&dir)?;
    let load = |split: Split| -> Result<Vec<Item>, String> {
        manifest
            .items
            .par_iter()
            .filter(|it| it.split == split)
            .map(|it| {
                let d = dir.join(&it.dir);
                let e = |e: &dyn std::fmt::Display| e.to_string();
                Ok(Item {
                    score: item_midi_score(&d).map_err(|x| e(&x))?,
                    changes_s: read_first_column(&d.join("bowchanges.txt"))
                        .map_err(|x| e(&x))?
                        .into_iter()
                        .filter(|t| *t >= 0.1)
                        .collect(),
                    strokes: read_strokes(&d.join("strokes.tsv")).map_err(|x| e(&x))?,
                })
            })
            .collect()
    };
    let val = load(Split::Val)?;
    println!("{} validation items", val.len());
    let gap_s = MidiBowing::default().legato_gap_s;
    let mut shares: Vec<f64> = val
        .iter()
        .map(|it| separated_share(&it.score, gap_s))
        .collect();
    shares.sort_by(f64::total_cmp);
    let at = |q: f64| {
        shares
            .get((q * shares.len().saturating_sub(1) as f64) as usize)
            .copied()
            .unwrap_or(0.0)
    };
    println!(
        "share of consecutive notes apart by a gap (notated timing below {}): min {:.3}, 5 % {:.3}, median {:.3}",
        MidiBowing::default().notated_below_share,
        at(0.0),
        at(0.05),
        at(0.5)
    );
    let notated = (val.iter())
        .filter(|it| timing_is_notated(&it.score, &MidiBowing::default()))
        .count();
    println!("{notated} items read as notated timing");
    let played = MidiBowing {
        notated_below_share: 0.0,
        ..MidiBowing::default()
    };
    println!(
        "{}",
        line("played-timing rules only", measure(&val, &played))
    );
    println!(
        "{}",
        line("default rules", measure(&val, &MidiBowing::default()))
    );
    let mut results = Vec::new();
    for legato_gap_s in [0.001, 0.005, 0.01, 0.02, 0.03] {
        for max_slur_notes in [2, 3, 4, 6] {
            for max_slur_notes_short in [2, 4, 8] {
                for max_bow_s in [1.5, 2.0, 3.0] {
                    for max_velocity_step in [10, 20, 127] {
                        let rules = MidiBowing {
                            legato_gap_s,
                            max_slur_notes,
                            max_slur_notes_short,
                            max_bow_s,
                            max_velocity_step,
                            ..MidiBowing::default()
                        };
                        let m = measure(&val, &rules);
                        let p = m.0 as f64 / m.2.max(1) as f64;
                        let r = m.0 as f64 / m.1.max(1) as f64;
                        results.push((performance::f_measure(p, r), rules, m));
                    }
                }
            }
        }
    }
    results.sort_by(|a, b| b.0.total_cmp(&a.0));
    for gap in [0.001, 0.005, 0.01, 0.02, 0.03] {
        if let Some((_, rules, m)) = results.iter().find(|r| r.1.legato_gap_s == gap) {
            println!(
                "{}",
                line(&format!("best with a legato gap of {gap} s: {rules:?}"), *m)
            );
        }
    }
    for (_, rules, m) in results.iter().take(8) {
        println!("{}", line(&format!("{rules:?}"), *m));
    }
    let Some((_, best, _)) = results.first() else {
        return Ok(());
    };
    let train = load(Split::Train)?;
    println!("\n{} training items", train.len());
    println!(
        "{}",
        line("default rules", measure(&train, &MidiBowing::default()))
    );
    println!("{}", line("best on validation", measure(&train, best)));
    Ok(())
}
