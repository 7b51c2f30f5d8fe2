//! Training the bow-change CNN from scratch on a tiny synthetic corpus, in a few steps, then
//! using the weights through the facade. The real recipe (an 80-minute corpus, full epochs)
//! is in `crates/bowing-net/README.md`; this shows the API end to end in about a minute.
//!
//! `cargo run --release -p violin-train --example train_bowing [-- OUT_DIR]`

use bowing_net::TrainConfig;
use corpus::build::{build_corpus, CorpusConfig};
use corpus::etude::EtudeConfig;
use violin_skeleton::{load_audio, Pipeline};
use violin_train::bowing_data::load_dataset;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out_dir = std::env::args().nth(1).map_or_else(
        || std::env::temp_dir().join("train_bowing_example"),
        Into::into,
    );
    let corpus_dir = out_dir.join("corpus");
    // 1. Ten 15-second études from the built-in synthesizer (train, validation and test
    //    splits come from the item index).
    let cfg = CorpusConfig {
        minutes: 2.5,
        seed: 7,
        etude: EtudeConfig {
            target_s: 15.0,
            ..EtudeConfig::default()
        },
        ..CorpusConfig::default()
    };
    let manifest = build_corpus(&corpus_dir, &cfg, &|_, _| {})?;
    println!(
        "corpus: {} items in {}",
        manifest.items.len(),
        corpus_dir.display()
    );

    // 2. Mel spectrograms and bow-change labels, by split.
    let data = load_dataset(&corpus_dir, &|_, _| {})?;

    // 3. Two short epochs; the best weights (by validation F1) are written to `weights`.
    let weights = out_dir.join("bowing.safetensors");
    let train_cfg = TrainConfig {
        epochs: 2,
        max_steps_per_epoch: Some(20),
        data_description: "train_bowing example".into(),
        ..TrainConfig::default()
    };
    let report = bowing_net::train(&data, &train_cfg, &weights, false, &mut |p| {
        if let Some(f1) = p.val_f1 {
            println!(
                "epoch {}: loss {:.4}, validation F1 {f1:.3}",
                p.epoch + 1,
                p.loss
            );
        }
    })?;
    println!(
        "kept epoch {} (validation F1 {:.3} at threshold 0.5) → {}",
        report.best_epoch + 1,
        report.best_val_f1,
        weights.display()
    );

    // 4. The new weights in the pipeline, on a test item.
    let pipeline = Pipeline::builder().bowing_weights(&weights).build();
    let test_item = manifest
        .items
        .iter()
        .find(|it| it.split == corpus::manifest::Split::Test)
        .ok_or("the corpus has no test item")?;
    let audio = load_audio(corpus_dir.join(&test_item.dir).join("audio.wav"))?;
    let analysis = pipeline.analyze(&audio)?;
    println!(
        "{}: {} bow changes found with the new weights",
        test_item.dir,
        analysis.bow_changes_s.len()
    );
    Ok(())
}
