//! Evaluates bowing-net weights on every recording of a data folder (all splits, or only the
//! test split with `--test`, only the validation split with `--val`) and prints the scores
//! as JSON (overall and per renderer).
//!
//! ```sh
//! cargo run --release -p violin-train --example evaluate_bowing -- DATA_DIR [WEIGHTS] [--test|--val]
//! ```
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::PathBuf;

use bowing_net::BowChangeDetector;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let test_only = args.iter().any(|a| a == "--test");
    let val_only = args.iter().any(|a| a == "--val");
    let paths: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    let dir = PathBuf::from(
        paths
            .first()
            .ok_or("usage: evaluate DATA_DIR [WEIGHTS] [--test|--val]")?,
    );
    let detector = match paths.get(1) {
        Some(w) => BowChangeDetector::load(w.as_ref())?,
        None => BowChangeDetector::pretrained()?,
    };
    let data = violin_train::bowing_data::load_dataset(&dir, &|_, _| {})?;
    let recs: Vec<_> = if test_only {
        data.test
    } else if val_only {
        data.val
    } else {
        data.train
            .into_iter()
            .chain(data.val)
            .chain(data.test)
            .collect()
    };
    let t0 = std::time::Instant::now();
    let eval = bowing_net::metrics::evaluate(&detector, &recs)?;
    let s = &eval.all;
    eprintln!(
        "{} recordings ({:.1} min) in {:.2} s: F1 ±2 {:.3}, ±3 {:.3} (P {:.3} R {:.3}); onsets ±3 {:.3}; slur precision {:.3}",
        s.recordings,
        s.minutes,
        t0.elapsed().as_secs_f64(),
        s.changes_2.f1(),
        s.changes_3.f1(),
        s.changes_3.precision(),
        s.changes_3.recall(),
        s.onsets_3.f1(),
        s.slur_precision()
    );
    println!("{}", serde_json::to_string_pretty(&eval)?);
    Ok(())
}
