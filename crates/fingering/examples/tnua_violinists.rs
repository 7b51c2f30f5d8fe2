//! How far one violinist agrees with the others, beside the learned planner scored against
//! the same others: the human reference for issue #22's agreement measures, on the ten
//! training pieces of the TNUA dataset (the reserved pieces are not read).
//!
//! ```text
//! cargo run --release -p fingering --features train --example tnua_violinists -- DIR
//! ```
//!
//! For each training piece and each violinist v, v's own fingering (where v labelled the
//! note) is scored like a plan against the other violinists' labels of that note: the share
//! on the same string, the share on the same string and position (an open string on both
//! sides matches), and whether at least one of them agrees on string and position. The
//! learned planner, fitted leave-one-piece-out on the other nine pieces with the shipped
//! settings, is scored on the same notes against the same violinists, so the two columns
//! differ only in who chose the fingering. A last row takes, per note, the place most of the
//! others chose (an oracle no planner can be: it reads the answers); notes where that label
//! does not play the note's pitch (the dataset has a few) are left out of that row, as is
//! a violinist's own label that does not play the pitch.

use std::collections::BTreeMap;
use std::path::PathBuf;

use fingering::train::{
    count_span, fit_with_fifths, read_tnua_dir, Agreement, Label, Piece, RESERVED_PIECES,
};
use fingering::{Fingering, FingeringPlanner, LearnedParams, LearnedPlanner};

/// The place most of `others` chose for `midi` (ties: the first in label order).
fn modal(midi: u8, others: &[Label]) -> Option<Fingering> {
    let mut counts: BTreeMap<(u8, u8, bool), (usize, usize)> = BTreeMap::new();
    for (i, l) in others.iter().enumerate() {
        let key = (
            l.string,
            if l.finger == 0 { 0 } else { l.position },
            l.finger == 0,
        );
        let e = counts.entry(key).or_insert((0, i));
        e.0 += 1;
    }
    let (_, first) = counts
        .values()
        .max_by_key(|(n, first)| (*n, std::cmp::Reverse(*first)))?;
    others[*first].to_fingering(midi)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .ok_or("usage: tnua_violinists DIR (the TNUA dataset's folder of vio*_*.csv)")?;
    let pieces = read_tnua_dir(&dir)?;
    let train: Vec<&Piece> = pieces
        .iter()
        .filter(|p| !RESERVED_PIECES.contains(&p.name.as_str()))
        .collect();
    // The shipped settings (smoothing, weights and span context of `data/learned_tnua.tsv`).
    let shipped = LearnedParams::shipped()?;
    let h = [
        shipped.alpha,
        shipped.beta,
        shipped.lambda,
        shipped.mu,
        shipped.gamma_string,
        shipped.gamma_position,
    ];
    let (mut human, mut planner, mut oracle) = (
        Agreement::default(),
        Agreement::default(),
        Agreement::default(),
    );
    let mut per_violinist: BTreeMap<usize, (Agreement, Agreement)> = BTreeMap::new();
    for piece in &train {
        let rest: Vec<&Piece> = train
            .iter()
            .filter(|p| p.name != piece.name)
            .copied()
            .collect();
        let mut params = fit_with_fifths(&rest, h, None);
        if let Some(span) = shipped.span {
            count_span(&mut params, &rest, span);
        }
        let plan = LearnedPlanner::new(&params).plan(&piece.midi)?;
        for ((labels, &midi), planned) in piece.labels.iter().zip(&piece.midi).zip(&plan) {
            for (v, own) in labels.iter().enumerate() {
                let Some(own) = own else { continue };
                let Some(own_place) = own.to_fingering(midi) else {
                    continue;
                };
                let others: Vec<Label> = labels
                    .iter()
                    .enumerate()
                    .filter(|(w, _)| *w != v)
                    .filter_map(|(_, l)| *l)
                    .collect();
                if others.is_empty() {
                    continue;
                }
                human.add_note(&own_place, &others);
                planner.add_note(planned, &others);
                if let Some(m) = modal(midi, &others) {
                    oracle.add_note(&m, &others);
                }
                let e = per_violinist.entry(v).or_default();
                e.0.add_note(&own_place, &others);
                e.1.add_note(planned, &others);
            }
        }
    }
    println!(
        "## One violinist against the others ({} training pieces; notes counted once per violinist)",
        train.len()
    );
    println!("| chooser | notes | string | string+position | ≥ 1 of the others |");
    println!("|---|---|---|---|---|");
    println!(
        "{}",
        human.markdown_row("the violinist (mean over violinists)")
    );
    println!(
        "{}",
        planner.markdown_row("learned planner (LOPO, shipped settings)")
    );
    println!(
        "{}",
        oracle.markdown_row("the others' most common place (oracle)")
    );
    println!("\nper violinist (violinist / planner on the same notes):");
    for (v, (h, p)) in &per_violinist {
        let (hs, hp, ha) = h.shares();
        let (ps, pp, pa) = p.shares();
        println!(
            "violinist {:>2}: {hs:.3} / {hp:.3} / {ha:.3}   planner {ps:.3} / {pp:.3} / {pa:.3}   ({} notes)",
            v + 1,
            h.notes
        );
    }
    Ok(())
}
