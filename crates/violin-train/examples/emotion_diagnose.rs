//! The underfitting diagnosis of the README: trains emotion-net with settings from a JSON
//! file (any subset of `TrainConfig`'s fields, e.g. dropout off:
//! `{"model": {"conv_dropout": 0, "dense_dropout": 0, "gru_dropout": 0}}`), prints one line
//! per epoch (time, training loss, validation Pearson r) and then the kept weights' r on the
//! *training* tracks, so fitting and generalising can be told apart. The test split is not
//! looked at. With `--csv` a corpus trains on its `arousal.csv` as written (e.g. the first
//! version of the proxy) instead of the recomputed proxy.
//!
//! ```sh
//! cargo run --release -p violin-train --example emotion_diagnose -- DATA_DIR OUT.safetensors [CONFIG.json] [--csv]
//! ```

use std::path::PathBuf;

use emotion_net::TrainConfig;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let all: Vec<String> = std::env::args().skip(1).collect();
    let csv = all.iter().any(|a| a == "--csv");
    let args: Vec<&String> = all.iter().filter(|a| !a.starts_with("--")).collect();
    let usage = "usage: diagnose DATA_DIR OUT.safetensors [CONFIG.json] [--csv]";
    let data_dir = PathBuf::from(args.first().ok_or(usage)?);
    let out = PathBuf::from(args.get(1).ok_or(usage)?);
    let target = if csv {
        violin_train::emotion_data::CorpusTarget::File
    } else {
        violin_train::emotion_data::CorpusTarget::Proxy
    };
    let cfg: TrainConfig = match args.get(2) {
        Some(p) => serde_json::from_str(&std::fs::read_to_string(p.as_str())?)?,
        None => TrainConfig::default(),
    };
    let t0 = std::time::Instant::now();
    let data = if data_dir.join("manifest.json").is_file() {
        violin_train::emotion_data::load_corpus_with(&data_dir, target, &|_, _| {})?
    } else {
        violin_train::emotion_data::load_dataset(&data_dir, &|_, _| {})?
    };
    eprintln!(
        "loaded {} train / {} validation tracks in {:.1} s; config {}",
        data.train.len(),
        data.val.len(),
        t0.elapsed().as_secs_f64(),
        serde_json::to_string(&cfg)?
    );
    let report = emotion_net::train(&data, &cfg, &out, false, &mut |p| {
        if let Some(r) = p.val_r {
            eprintln!(
                "epoch {:2} {:6.1} s lr {:.2e} loss {:.4} val r {:.3} best {:.3}",
                p.epoch + 1,
                p.elapsed_s,
                p.learning_rate,
                p.loss,
                r,
                p.best_r
            );
        }
    })?;
    let est = emotion_net::ArousalEstimator::load(&out)?;
    let (train_r, train_rmse) = emotion_net::evaluate::score(est.net(), &data.train)?;
    eprintln!("kept weights on the training tracks: r {train_r:.3}, RMSE {train_rmse:.3}");
    println!("{}", serde_json::to_string_pretty(&report)?);
    Ok(())
}
