//! Evaluates emotion-net weights on every track of a data folder (all splits, or the test
//! split with `--test`) and prints Pearson r and RMSE as JSON.
//!
//! ```sh
//! cargo run --release -p violin-train --example evaluate_arousal -- DATA_DIR [WEIGHTS] [--test]
//! ```

use std::path::PathBuf;

use emotion_net::ArousalEstimator;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let test_only = args.iter().any(|a| a == "--test");
    let paths: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    let dir = PathBuf::from(
        paths
            .first()
            .ok_or("usage: evaluate DATA_DIR [WEIGHTS] [--test]")?,
    );
    let est = match paths.get(1) {
        Some(w) => ArousalEstimator::load(w.as_ref())?,
        None => ArousalEstimator::pretrained()?,
    };
    let data = violin_train::emotion_data::load_dataset(&dir, &|_, _| {})?;
    let tracks: Vec<_> = if test_only {
        data.test
    } else {
        data.train
            .into_iter()
            .chain(data.val)
            .chain(data.test)
            .collect()
    };
    let t0 = std::time::Instant::now();
    let eval = emotion_net::evaluate::evaluate(est.net(), &tracks)?;
    eprintln!(
        "{} tracks ({:.1} min) in {:.2} s: Pearson r {:.3}, RMSE {:.3}",
        eval.all.tracks,
        eval.all.minutes,
        t0.elapsed().as_secs_f64(),
        eval.all.pearson_r,
        eval.all.rmse
    );
    println!("{}", serde_json::to_string_pretty(&eval)?);
    Ok(())
}
