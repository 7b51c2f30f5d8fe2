//! How the learned planner's agreement with the TNUA violinists grows with the number of
//! training pieces (a diagnostic of issue #22's goals; the shipped settings throughout).
//!
//! ```text
//! cargo run --release -p fingering --features train --example tnua_curve -- DIR              # 11 s
//! cargo run --release -p fingering --features train --example tnua_curve -- DIR --reserved   # 6 s
//! ```
//!
//! Without `--reserved` it reads the ten training pieces only and prints (a) the planner
//! fitted on all ten and scored on the same ten (what the model can fit at all) and (b) the
//! leave-one-piece-out learning curve: each piece scored by a planner fitted on k of the
//! other nine (k = 1 … 9; `--subsets N` random subsets per piece and k, 10 by default, drawn
//! with a fixed seed; k = 9 is plain leave-one-piece-out). With `--reserved` it scores the
//! reserved pieces by planners fitted on k of the ten training pieces (k = 1 … 10): the
//! reserved pieces are scored, never fitted on.
//!
//! Each line gives the pooled string / string+position / at-least-one-violinist agreement;
//! the fit of agreement = a + b·ln k over k ≥ 3 and the k at which it would reach each of
//! the issue's goals (.85 / .75 / .95) follow.

use std::path::PathBuf;

use fingering::train::{
    agreement, count_span, fit, read_tnua_dir, Agreement, Piece, RESERVED_PIECES,
};
use fingering::{FingeringPlanner, LearnedPlanner, SpanContext};

/// The shipped hyper-parameters (`tnua --fixed 20,200,2,2,0.5,0.5 --span 4,0,2,1`).
const SHIPPED: [f64; 6] = [20.0, 200.0, 2.0, 2.0, 0.5, 0.5];
const SHIPPED_SPAN: SpanContext = SpanContext {
    ahead: 4,
    behind: 0,
    alpha: 2.0,
    weight: 1.0,
};
const GOALS: [f64; 3] = [0.85, 0.75, 0.95];

type BoxError = Box<dyn std::error::Error>;

fn fitted(pieces: &[&Piece]) -> LearnedPlanner {
    let mut p = fit(pieces, SHIPPED);
    count_span(&mut p, pieces, SHIPPED_SPAN);
    LearnedPlanner::new(&p)
}

fn score(planner: &LearnedPlanner, pieces: &[&Piece]) -> Result<Agreement, BoxError> {
    let mut total = Agreement::default();
    for piece in pieces {
        total.add(&agreement(piece, &planner.plan(&piece.midi)?));
    }
    Ok(total)
}

/// `k` of `from`, drawn by a seeded Fisher–Yates shuffle.
fn draw<'a>(from: &[&'a Piece], k: usize, state: &mut u64) -> Vec<&'a Piece> {
    let mut idx: Vec<usize> = (0..from.len()).collect();
    for a in (1..idx.len()).rev() {
        // xorshift64
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        idx.swap(a, (*state % (a as u64 + 1)) as usize);
    }
    idx[..k].iter().map(|&j| from[j]).collect()
}

/// Prints the least-squares fit of agreement = a + b·ln k over `k ≥ 3` for each measure.
fn extrapolate(curve: &[(usize, Agreement)]) {
    let points: Vec<(f64, [f64; 3])> = curve
        .iter()
        .filter(|(k, _)| *k >= 3)
        .map(|(k, a)| {
            let (s, sp, any) = a.shares();
            ((*k as f64).ln(), [s, sp, any])
        })
        .collect();
    let n = points.len() as f64;
    for (m, name) in ["string", "string+position", "≥ 1 violinist"]
        .iter()
        .enumerate()
    {
        let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
        let my = points.iter().map(|p| p.1[m]).sum::<f64>() / n;
        let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1[m] - my)).sum();
        let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
        let b = sxy / sxx;
        let a = my - b * mx;
        let at_goal = ((GOALS[m] - a) / b).exp();
        println!(
            "{name}: a + b·ln k with a = {a:.4}, b = {b:.4} per e-fold; goal {} at k ≈ {at_goal:.0}",
            GOALS[m]
        );
    }
}

fn main() -> Result<(), BoxError> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = args
        .first()
        .filter(|a| !a.starts_with("--"))
        .map(PathBuf::from)
        .ok_or("usage: tnua_curve DIR [--reserved] [--subsets N]")?;
    let subsets: usize = match args.iter().position(|a| a == "--subsets") {
        Some(i) => args.get(i + 1).ok_or("--subsets needs N")?.parse()?,
        None => 10,
    };
    let reserved = args.iter().any(|a| a == "--reserved");
    let pieces = read_tnua_dir(&dir)?;
    let is_reserved = |p: &&Piece| RESERVED_PIECES.contains(&p.name.as_str());
    let train: Vec<&Piece> = pieces.iter().filter(|p| !is_reserved(p)).collect();
    let held: Vec<&Piece> = pieces.iter().filter(is_reserved).collect();
    if train.len() < 2 || (reserved && held.is_empty()) {
        return Err(format!("{}: too few TNUA pieces", dir.display()).into());
    }
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut curve = Vec::new();
    if reserved {
        println!("reserved pieces scored by planners fitted on k training pieces");
        for k in 1..=train.len() {
            let reps = if k == train.len() { 1 } else { subsets };
            let mut total = Agreement::default();
            for _ in 0..reps {
                total.add(&score(&fitted(&draw(&train, k, &mut state)), &held)?);
            }
            curve.push((k, total));
        }
    } else {
        let all = score(&fitted(&train), &train)?;
        println!(
            "{}",
            all.markdown_row("in-sample: fitted on all, scored on them")
        );
        println!("leave-one-piece-out with k of the other pieces");
        for k in 1..train.len() {
            let reps = if k == train.len() - 1 { 1 } else { subsets };
            let mut total = Agreement::default();
            for (i, piece) in train.iter().enumerate() {
                let others: Vec<&Piece> = (train.iter().enumerate())
                    .filter(|(j, _)| *j != i)
                    .map(|(_, p)| *p)
                    .collect();
                for _ in 0..reps {
                    let planner = fitted(&draw(&others, k, &mut state));
                    total.add(&score(&planner, &[*piece])?);
                }
            }
            curve.push((k, total));
        }
    }
    println!("| k | notes scored | string | string+position | ≥ 1 violinist |");
    println!("|---|---|---|---|---|");
    for (k, a) in &curve {
        println!("{}", a.markdown_row(&k.to_string()));
    }
    extrapolate(&curve);
    Ok(())
}
