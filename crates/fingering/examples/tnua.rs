//! Trains and evaluates the learned fingering planner on the TNUA violin fingering dataset
//! (Chen et al., IUI 2021, github.com/Tsung-Ping/Violin-Fingering-Generation), read from a
//! directory you give (the dataset states no licence, so it is not in the repository).
//!
//! ```text
//! cargo run --release -p fingering --features train --example tnua -- DIR            # LOPO tuning
//! cargo run --release -p fingering --features train --example tnua -- DIR --write data/learned_tnua.tsv
//! cargo run --release -p fingering --features train --example tnua -- DIR --reserved # final evaluation
//! cargo run --release -p fingering --features train --example tnua -- DIR --fifths 2  # LOPO, places also counted a fifth up/down
//! ```
//!
//! The pieces bach1, bach2, flower and mend1 are reserved for the final evaluation: they
//! are never read for training, tuning or leave-one-piece-out (LOPO). Tuning picks the
//! smoothing and weights with the best LOPO string+position agreement over the other ten
//! pieces; `--write` fits those on all ten and writes the parameters; `--reserved`
//! evaluates the shipped parameters and the baselines on the reserved pieces.

use std::path::PathBuf;

use fingering::train::{
    agreement, fit_with_fifths, read_tnua_dir, Agreement, Piece, RESERVED_PIECES,
};
use fingering::{
    Fingering, FingeringPlanner, FingeringTable, GreedyPlanner, LearnedParams, LearnedPlanner,
    OptimalPlanner,
};

/// "Highest string, lowest position": per note, the highest string that plays it, in the
/// lowest position (1st or above) that does.
struct HighestString;

impl FingeringPlanner for HighestString {
    fn plan(&self, midi: &[u8]) -> Result<Vec<Fingering>, fingering::FingeringError> {
        let table = FingeringTable::physical();
        midi.iter()
            .enumerate()
            .map(|(index, &m)| {
                table
                    .places(m)
                    .iter()
                    .filter(|f| f.position >= 1)
                    .max_by_key(|f| (f.string, std::cmp::Reverse(f.position)))
                    .copied()
                    .ok_or(fingering::FingeringError::UnplayablePitch { index, midi: m })
            })
            .collect()
    }
}

fn evaluate(planner: &dyn FingeringPlanner, pieces: &[&Piece]) -> (Agreement, Vec<Agreement>) {
    let mut total = Agreement::default();
    let mut each = Vec::new();
    for piece in pieces {
        let a = match planner.plan(&piece.midi) {
            Ok(plan) => agreement(piece, &plan),
            Err(e) => {
                eprintln!("{}: {e}", piece.name);
                Agreement::default()
            }
        };
        total.add(&a);
        each.push(a);
    }
    (total, each)
}

fn lopo(train: &[&Piece], h: [f64; 6], fifths: Option<u32>) -> (Agreement, Vec<Agreement>) {
    let mut total = Agreement::default();
    let mut each = Vec::new();
    for (i, held) in train.iter().enumerate() {
        let rest: Vec<&Piece> = train
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .map(|(_, p)| *p)
            .collect();
        let planner = LearnedPlanner::new(&fit_with_fifths(&rest, h, fifths));
        let (a, _) = evaluate(&planner, &[held]);
        total.add(&a);
        each.push(a);
    }
    (total, each)
}

fn row(name: &str, a: &Agreement) -> String {
    let (s, sp, any) = a.shares();
    format!(
        "| {name} | {} | {:.3} | {:.3} | {:.3} |",
        a.notes, s, sp, any
    )
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = args
        .iter()
        .enumerate()
        .find(|(i, a)| {
            !a.starts_with("--")
                && (*i == 0 || !["--write", "--debug", "--fifths"].contains(&args[i - 1].as_str()))
        })
        .map(|(_, a)| a)
        .map(PathBuf::from)
        .ok_or("usage: tnua DIR [--write PARAMS.tsv] [--reserved] [--fifths W] [--debug PIECE]")?;
    let write = args
        .iter()
        .position(|a| a == "--write")
        .and_then(|i| args.get(i + 1))
        .map(PathBuf::from);
    let reserved = args.iter().any(|a| a == "--reserved");
    let debug = args
        .iter()
        .position(|a| a == "--debug")
        .and_then(|i| args.get(i + 1))
        .cloned();
    let fifths: Option<u32> = args
        .iter()
        .position(|a| a == "--fifths")
        .and_then(|i| args.get(i + 1))
        .map(|w| w.parse())
        .transpose()?;
    let pieces = read_tnua_dir(&dir)?;
    let train: Vec<&Piece> = pieces
        .iter()
        .filter(|p| !RESERVED_PIECES.contains(&p.name.as_str()))
        .collect();
    let held: Vec<&Piece> = pieces
        .iter()
        .filter(|p| RESERVED_PIECES.contains(&p.name.as_str()))
        .collect();

    let greedy = GreedyPlanner::new(FingeringTable::physical());
    let optimal = OptimalPlanner::default();
    let baselines: [(&str, &dyn FingeringPlanner); 3] = [
        ("greedy (physical table)", &greedy),
        ("optimal (Viterbi, default weights)", &optimal),
        ("highest string, lowest position", &HighestString),
    ];

    if reserved {
        println!("## Reserved pieces ({})", RESERVED_PIECES.join(", "));
        println!("| planner | notes | string | string+position | ≥ 1 violinist |");
        println!("|---|---|---|---|---|");
        let learned = LearnedPlanner::default();
        let (all, each) = evaluate(&learned, &held);
        println!("{}", row("learned (shipped)", &all));
        for (name, p) in baselines {
            println!("{}", row(name, &evaluate(p, &held).0));
        }
        println!("\nper piece, learned:");
        for (p, a) in held.iter().zip(&each) {
            println!("{}", row(&p.name, a));
        }
        return Ok(());
    }

    if let Some(name) = debug {
        let h = [5.0, 200.0, 2.0, 0.5, 0.0, 0.0];
        let rest: Vec<&Piece> = train.iter().filter(|p| p.name != name).copied().collect();
        let Some(piece) = train.iter().find(|p| p.name == name) else {
            return Err("no such training piece".into());
        };
        let plan = LearnedPlanner::new(&fit_with_fifths(&rest, h, fifths)).plan(&piece.midi)?;
        for (i, (f, labels)) in plan.iter().zip(&piece.labels).enumerate() {
            let ok = labels.iter().flatten().any(|l| l.same_string_position(f));
            let l: Vec<String> = labels
                .iter()
                .map(|l| {
                    l.map_or("-".into(), |l| {
                        format!("{}{}{}", l.string, l.position, l.finger)
                    })
                })
                .collect();
            println!(
                "{i:4} {:3} {}{}{}{:?} {} {}",
                piece.midi[i],
                f.string.number(),
                f.position,
                f.finger,
                f.placement,
                if ok { "  " } else { "XX" },
                l.join(" ")
            );
        }
        return Ok(());
    }
    let mut grid = Vec::new();
    for alpha in [1.0, 5.0, 20.0] {
        for beta in [50.0, 200.0] {
            for lambda in [1.0, 1.5, 2.0, 3.0] {
                for mu in [0.5, 2.0] {
                    for gs in [0.0, 0.25, 0.5] {
                        for gp in [0.0, 0.25, 0.5] {
                            grid.push([alpha, beta, lambda, mu, gs, gp]);
                        }
                    }
                }
            }
        }
    }
    let mut best = (f64::NEG_INFINITY, grid[0]);
    for h in &grid {
        let (a, _) = lopo(&train, *h, fifths);
        let (s, sp, any) = a.shares();
        eprintln!("{h:?}: {s:.3} {sp:.3} {any:.3}");
        if sp > best.0 {
            best = (sp, *h);
        }
    }
    let h = best.1;
    println!(
        "## Leave-one-piece-out over {} training pieces (alpha, beta, lambda, mu, gamma_string, gamma_position = {h:?})",
        train.len()
    );
    println!("| planner | notes | string | string+position | ≥ 1 violinist |");
    println!("|---|---|---|---|---|");
    let (all, each) = lopo(&train, h, fifths);
    println!("{}", row("learned (LOPO)", &all));
    for (name, p) in baselines {
        println!("{}", row(name, &evaluate(p, &train).0));
    }
    println!("\nper held-out piece, learned:");
    for (p, a) in train.iter().zip(&each) {
        println!("{}", row(&p.name, a));
    }
    if let Some(path) = write {
        let params: LearnedParams = fit_with_fifths(&train, h, fifths);
        std::fs::write(&path, params.to_tsv())?;
        println!(
            "\nparameters fitted on all {} training pieces written to {}",
            train.len(),
            path.display()
        );
    }
    Ok(())
}
