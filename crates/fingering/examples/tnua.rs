//! Trains and evaluates the learned fingering planner on the TNUA violin fingering dataset
//! (Chen et al., IUI 2021, github.com/Tsung-Ping/Violin-Fingering-Generation), read from a
//! directory you give (the dataset states no licence, so it is not in the repository).
//!
//! ```text
//! cargo run --release -p fingering --features train --example tnua -- DIR            # LOPO tuning
//! cargo run --release -p fingering --features train --example tnua -- DIR --write data/learned_tnua.tsv
//! cargo run --release -p fingering --features train --example tnua -- DIR --reserved # final evaluation
//! cargo run --release -p fingering --features train --example tnua -- DIR --fifths 2  # LOPO, places also counted a fifth up/down
//! cargo run --release -p fingering --features train --example tnua -- DIR --fixed 20,200,2,2,0.5,0.5 --span 4,0,2,1
//! cargo run --release -p fingering --features train --example tnua -- DIR --small-grid --span off --span 4,0,2,1 --nested
//! cargo run --release -p fingering --features train --example tnua -- DIR --fixed 20,200,2,2,0.5,0.5 --span 4,0,2,1 --ytvf YTVF_DIR
//! ```
//!
//! `--span AHEAD,BEHIND,ALPHA,WEIGHT` (repeatable; `off` = none) gives the span contexts
//! tried ([`fingering::span`]); `--fixed A,B,L,M,GS,GP` replaces the hyper-parameter grid
//! by one point and `--small-grid` by 12; `--nested` chooses the settings for each held-out
//! piece by LOPO over the other nine (nested LOPO: how good the choice itself is).
//! `--ytvf YTVF_DIR` (the YTVF dataset's `YTVF_dataset` folder, [`fingering::ytvf`]) also
//! evaluates the planner fitted on the ten training pieces on YTVF's 30 works; with
//! `--ytvf-train W` those works join every fit instead (each counted W times) and are not
//! evaluated.
//!
//! The pieces bach1, bach2, flower and mend1 are reserved for the final evaluation: they
//! are never read for training, tuning or leave-one-piece-out (LOPO). Tuning picks the
//! smoothing and weights with the best LOPO string+position agreement over the other ten
//! pieces; `--write` fits those on all ten and writes the parameters; `--reserved`
//! evaluates the shipped parameters and the baselines on the reserved pieces.

use std::path::{Path, PathBuf};

use fingering::train::{
    agreement, count_span, fit_with_fifths, read_tnua_dir, Agreement, Piece, RESERVED_PIECES,
};
use fingering::ytvf::read_ytvf_dir;
use fingering::SpanContext;
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

/// What is counted besides the training pieces themselves.
struct Counting<'a> {
    /// `--fifths W`: places also counted a fifth up and down.
    fifths: Option<u32>,
    /// `--ytvf-train W`: the YTVF pieces, each W times, in every fit.
    extra: Vec<&'a Piece>,
}

/// The parameters fitted on `pieces` (and `counting`'s extra pieces) with hyper-parameters
/// `h` and span context `span`.
fn fit(
    pieces: &[&Piece],
    h: [f64; 6],
    counting: &Counting,
    span: Option<SpanContext>,
) -> LearnedParams {
    let mut all = pieces.to_vec();
    all.extend(counting.extra.iter().copied());
    let mut p = fit_with_fifths(&all, h, counting.fifths);
    if let Some(span) = span {
        count_span(&mut p, &all, span);
    }
    p
}

/// The values of every `--span` flag (`off` = `None`); `[None]` without one.
fn spans(args: &[String]) -> Result<Vec<Option<SpanContext>>, String> {
    let mut out = Vec::new();
    for (i, a) in args.iter().enumerate() {
        if a != "--span" {
            continue;
        }
        let v = args
            .get(i + 1)
            .ok_or("--span needs AHEAD,BEHIND,ALPHA,WEIGHT or off")?;
        if v == "off" {
            out.push(None);
            continue;
        }
        let x: Vec<f64> = numbers(v)?;
        let [ahead, behind, alpha, weight] = x[..] else {
            return Err(format!("--span {v}: needs AHEAD,BEHIND,ALPHA,WEIGHT"));
        };
        out.push(Some(SpanContext {
            ahead: ahead as usize,
            behind: behind as usize,
            alpha,
            weight,
        }));
    }
    if out.is_empty() {
        out.push(None);
    }
    Ok(out)
}

fn numbers(v: &str) -> Result<Vec<f64>, String> {
    v.split(',')
        .map(|x| x.parse::<f64>().map_err(|e| format!("{x}: {e}")))
        .collect()
}

/// Nested leave-one-piece-out: for each held-out piece, the settings (of `grid` × `spans`)
/// with the best LOPO string+position over the other nine pieces, fitted on those nine.
fn nested(train: &[&Piece], grid: &[[f64; 6]], spans: &[Option<SpanContext>], counting: &Counting) {
    let mut total = Agreement::default();
    for (i, held) in train.iter().enumerate() {
        let rest: Vec<&Piece> = (train.iter().enumerate())
            .filter(|(j, _)| *j != i)
            .map(|(_, p)| *p)
            .collect();
        let mut best = (f64::NEG_INFINITY, grid[0], spans[0]);
        for span in spans {
            for h in grid {
                let sp = lopo(&rest, *h, counting, *span).0.shares().1;
                if sp > best.0 {
                    best = (sp, *h, *span);
                }
            }
        }
        let planner = LearnedPlanner::new(&fit(&rest, best.1, counting, best.2));
        let (a, _) = evaluate(&planner, &[held]);
        println!("{} {:?} {:?}", a.markdown_row(&held.name), best.1, best.2);
        total.add(&a);
    }
    println!("{}", total.markdown_row("nested LOPO"));
}

fn lopo(
    train: &[&Piece],
    h: [f64; 6],
    counting: &Counting,
    span: Option<SpanContext>,
) -> (Agreement, Vec<Agreement>) {
    let mut total = Agreement::default();
    let mut each = Vec::new();
    for (i, held) in train.iter().enumerate() {
        let rest: Vec<&Piece> = train
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .map(|(_, p)| *p)
            .collect();
        let planner = LearnedPlanner::new(&fit(&rest, h, counting, span));
        let (a, _) = evaluate(&planner, &[held]);
        total.add(&a);
        each.push(a);
    }
    (total, each)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = args
        .iter()
        .enumerate()
        .find(|(i, a)| {
            !a.starts_with("--")
                && (*i == 0
                    || ![
                        "--write",
                        "--debug",
                        "--fifths",
                        "--span",
                        "--fixed",
                        "--ytvf",
                        "--ytvf-train",
                    ]
                    .contains(&args[i - 1].as_str()))
        })
        .map(|(_, a)| a)
        .map(PathBuf::from)
        .ok_or(
            "usage: tnua DIR [--write PARAMS.tsv] [--reserved] [--fifths W] [--debug PIECE] \
             [--span A,B,ALPHA,W|off]… [--fixed A,B,L,M,GS,GP | --small-grid] [--nested] \
             [--ytvf YTVF_DIR [--ytvf-train W]]",
        )?;
    let spans = spans(&args)?;
    let fixed: Option<[f64; 6]> = args
        .iter()
        .position(|a| a == "--fixed")
        .and_then(|i| args.get(i + 1))
        .map(|v| {
            numbers(v)?
                .try_into()
                .map_err(|_| format!("--fixed {v}: needs 6 values"))
        })
        .transpose()?;
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
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
    };
    let ytvf = value("--ytvf")
        .map(|d| read_ytvf_dir(Path::new(d)))
        .transpose()?;
    let ytvf_train: usize = value("--ytvf-train")
        .map(|w| w.parse())
        .transpose()?
        .unwrap_or(0);
    if ytvf_train > 0 && ytvf.is_none() {
        return Err("--ytvf-train needs --ytvf YTVF_DIR".into());
    }
    let counting = Counting {
        fifths,
        extra: (ytvf.iter().flatten())
            .flat_map(|p| std::iter::repeat_n(p, ytvf_train))
            .collect(),
    };
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
        println!("{}", all.markdown_row("learned (shipped)"));
        if !counting.extra.is_empty() {
            let h = fixed.ok_or("--reserved with --ytvf-train needs --fixed")?;
            let planner = LearnedPlanner::new(&fit(&train, h, &counting, spans[0]));
            let name = format!("learned, + YTVF ×{ytvf_train} in training");
            println!("{}", evaluate(&planner, &held).0.markdown_row(&name));
        }
        for (name, p) in baselines {
            println!("{}", evaluate(p, &held).0.markdown_row(name));
        }
        println!("\nper piece, learned:");
        for (p, a) in held.iter().zip(&each) {
            println!("{}", a.markdown_row(&p.name));
        }
        return Ok(());
    }

    if let Some(name) = debug {
        let h = fixed.unwrap_or([20.0, 200.0, 1.5, 2.0, 0.5, 0.5]);
        let rest: Vec<&Piece> = train.iter().filter(|p| p.name != name).copied().collect();
        let Some(piece) = train.iter().find(|p| p.name == name) else {
            return Err("no such training piece".into());
        };
        let plan = LearnedPlanner::new(&fit(&rest, h, &counting, spans[0])).plan(&piece.midi)?;
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
    if let Some(h) = fixed {
        grid = vec![h];
    } else if args.iter().any(|a| a == "--small-grid") {
        grid.clear();
        for alpha in [5.0, 20.0] {
            for lambda in [1.5, 2.0, 3.0] {
                for gp in [0.25, 0.5] {
                    grid.push([alpha, 200.0, lambda, 2.0, 0.5, gp]);
                }
            }
        }
    }
    if args.iter().any(|a| a == "--nested") {
        nested(&train, &grid, &spans, &counting);
        return Ok(());
    }
    let mut best = (f64::NEG_INFINITY, grid[0], spans[0]);
    for span in &spans {
        for h in &grid {
            let (a, _) = lopo(&train, *h, &counting, *span);
            let (s, sp, any) = a.shares();
            eprintln!("{h:?} {span:?}: {s:.4} {sp:.4} {any:.4}");
            if sp > best.0 {
                best = (sp, *h, *span);
            }
        }
    }
    let (h, span) = (best.1, best.2);
    println!(
        "## Leave-one-piece-out over {} training pieces (alpha, beta, lambda, mu, gamma_string, gamma_position = {h:?}; span {span:?})",
        train.len()
    );
    println!("| planner | notes | string | string+position | ≥ 1 violinist |");
    println!("|---|---|---|---|---|");
    let (all, each) = lopo(&train, h, &counting, span);
    println!("{}", all.markdown_row("learned (LOPO)"));
    for (name, p) in baselines {
        println!("{}", evaluate(p, &train).0.markdown_row(name));
    }
    println!("\nper held-out piece, learned:");
    for (p, a) in train.iter().zip(&each) {
        println!("{}", a.markdown_row(&p.name));
    }
    if let (Some(ytvf), 0) = (&ytvf, ytvf_train) {
        let notes: usize = ytvf.iter().map(|p| p.midi.len()).sum();
        println!(
            "\n## Held out: YTVF ({} works, {notes} notes, one performer each), fitted on the {} training pieces",
            ytvf.len(),
            train.len()
        );
        println!("| planner | notes | string | string+position | ≥ 1 violinist |");
        println!("|---|---|---|---|---|");
        let ytvf: Vec<&Piece> = ytvf.iter().collect();
        let learned = LearnedPlanner::new(&fit(&train, h, &counting, span));
        println!("{}", evaluate(&learned, &ytvf).0.markdown_row("learned"));
        for (name, p) in baselines {
            println!("{}", evaluate(p, &ytvf).0.markdown_row(name));
        }
    }
    if let Some(path) = write {
        let params: LearnedParams = fit(&train, h, &counting, span);
        std::fs::write(&path, params.to_tsv())?;
        println!(
            "\nparameters fitted on all {} training pieces written to {}",
            train.len(),
            path.display()
        );
    }
    Ok(())
}
