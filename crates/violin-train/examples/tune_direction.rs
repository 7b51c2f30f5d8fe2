//! Re-tunes the direction decoder of a stroke-network weights file for the changes its
//! ensemble decoder now finds, as `train_strokes` tunes it after training: the analysis's
//! model (the shipped CNN and these weights averaged) on the corpus's validation items, the
//! grid of [`tune_direction_decoder`]. No test item is read. With `--write`, the tuned
//! decoder is stored in the weights file. With `--long-runs`, the grid also tries a stay
//! probability of its own (0.05, 0.1, 0.2, 0.35) for changes inside runs of at least 5, 6
//! or 8 frames of change probability at or above 0.65, the ensemble decoder's threshold
//! (`bowing_net::stroke::direction::LongRunStay`).
//!
//! ```text
//! cargo run --release -p violin-train --example tune_direction -- CORPUS W.safetensors [--long-runs] [--write]
//! ```

use std::path::PathBuf;

use bowing_net::stroke::direction::LongRunStay;
use bowing_net::stroke::StrokeDetector;
use bowing_net::{BowChangeDetector, BowingModel};
use violin_train::bowing_data::load_dataset;
use violin_train::stroke_directions::{
    direction_case, pooled_accuracy, tune_direction_decoder, tune_direction_decoder_with,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: tune_direction CORPUS W.safetensors [--long-runs] [--write]";
    let positional: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    let [corpus, weights] = positional.as_slice() else {
        return Err(usage.into());
    };
    let (corpus, weights) = (PathBuf::from(corpus), PathBuf::from(weights));
    let write = args.iter().any(|a| a == "--write");
    let val = load_dataset(&corpus, &|_, _| {})?.val;
    let strokes = StrokeDetector::load(&weights)?;
    let stored = strokes.direction_decoder();
    let model = BowingModel::Ensemble(Box::new(BowChangeDetector::pretrained()?), strokes);
    let pipeline = violin_skeleton::Pipeline::default();
    let mut cases = Vec::with_capacity(val.len());
    for r in &val {
        let audio = dsp_mel::load_audio(corpus::layout::item_audio(&corpus.join(&r.name)))?;
        cases.push(direction_case(r, &audio, &model, &pipeline)?);
    }
    let (tuned, accuracy) = if args.iter().any(|a| a == "--long-runs") {
        let mut options = vec![None];
        for min_frames in [5, 6, 8] {
            for stay_probability in [0.05f32, 0.1, 0.2, 0.35] {
                options.push(Some(LongRunStay {
                    min_frames,
                    threshold: 0.65,
                    stay_probability,
                }));
            }
        }
        tune_direction_decoder_with(&cases, &options)
    } else {
        tune_direction_decoder(&cases)
    };
    println!(
        "{} validation items: stored {stored:?}: {:.3}; rules alone {:.3}; re-tuned {tuned:?}: {accuracy:.3}",
        cases.len(),
        pooled_accuracy(&cases, stored),
        pooled_accuracy(&cases, None)
    );
    if write {
        let mut s = StrokeDetector::load(&weights)?;
        s.set_direction_decoder(tuned);
        s.save(&weights)?;
        eprintln!("wrote the direction decoder into {}", weights.display());
    }
    Ok(())
}
