//! Re-tunes the direction decoder of a stroke-network weights file for the changes its
//! ensemble decoder now finds, as `train_strokes` tunes it after training: the analysis's
//! model (the shipped CNN and these weights averaged) on the validation items of one or more
//! corpora (e.g. a corpus and its validation-violin renders, pooled), the grid of
//! [`tune_direction_decoder`]. No test item is read. With `--write`, the tuned
//! decoder is stored in the weights file. With `--long-runs`, the grid also tries a stay
//! probability of its own (0.05, 0.1, 0.2, 0.35) for changes inside runs of at least 5, 6
//! or 8 frames of change probability at or above 0.65, the ensemble decoder's threshold
//! (`bowing_net::stroke::direction::LongRunStay`).
//! With `--cnn C.safetensors`, the ensemble's CNN is `C` instead of the shipped one (as in
//! `validation_violin --cnn`). The best decoder of each `DirectionChoice` (the most
//! probable sequence, the most probable direction per stroke) is printed too.
//!
//! ```text
//! cargo run --release -p violin-train --example tune_direction -- CORPUS [CORPUS2 …] W.safetensors [--cnn C.safetensors] [--long-runs] [--write]
//! ```

use std::path::PathBuf;

use bowing_net::stroke::direction::{DirectionChoice, DirectionDecoder, LongRunStay};
use bowing_net::stroke::StrokeDetector;
use bowing_net::{BowChangeDetector, BowingModel};
use violin_train::bowing_data::load_dataset;
use violin_train::stroke_directions::{
    direction_case, pooled_accuracy, tune_direction_decoder_with, BOTH_CHOICES,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage =
        "usage: tune_direction CORPUS [CORPUS2 …] W.safetensors [--cnn C.safetensors] [--long-runs] [--write]";
    // Corpora are folders, the weights a file.
    let cnn_path = violin_train::example_args::flag_value(&args, "--cnn")?.map(PathBuf::from);
    let (corpora, weights): (Vec<PathBuf>, Vec<PathBuf>) = args
        .iter()
        .filter(|a| !a.starts_with("--"))
        .map(PathBuf::from)
        .filter(|p| Some(p) != cnn_path.as_ref())
        .partition(|p| p.is_dir());
    let ([weights], false) = (weights.as_slice(), corpora.is_empty()) else {
        return Err(usage.into());
    };
    let weights = weights.clone();
    let write = args.iter().any(|a| a == "--write");
    let strokes = StrokeDetector::load(&weights)?;
    let stored = strokes.direction_decoder();
    let cnn = match &cnn_path {
        Some(p) => BowChangeDetector::load(p)?,
        None => BowingModel::pretrained_ensemble_cnn()?,
    };
    let model = BowingModel::Ensemble(Box::new(cnn), strokes);
    let pipeline = violin_skeleton::Pipeline::default();
    let mut cases = Vec::new();
    for dir in &corpora {
        for r in &load_dataset(dir, &|_, _| {})?.val {
            let audio = dsp_mel::load_audio(corpus::layout::item_audio(&dir.join(&r.name)))?;
            cases.push(direction_case(r, &audio, &model, &pipeline)?);
        }
    }
    let mut options = vec![None];
    if args.iter().any(|a| a == "--long-runs") {
        for min_frames in [5, 6, 8] {
            for stay_probability in [0.05f32, 0.1, 0.2, 0.35] {
                options.push(Some(LongRunStay {
                    min_frames,
                    threshold: 0.65,
                    stay_probability,
                }));
            }
        }
    }
    // The best of each choice; the sequence wins ties, as in `tune_direction_decoder`.
    let [sequence, per_stroke] =
        BOTH_CHOICES.map(|choice| tune_direction_decoder_with(&cases, &options, &[choice]));
    for (choice, (best, acc)) in BOTH_CHOICES.iter().zip([sequence, per_stroke]) {
        println!("best with {choice:?}: {best:?}: {acc:.4}");
    }
    if let Some(stored) = stored {
        let choice = DirectionChoice::MostProbablePerStroke;
        let acc = pooled_accuracy(&cases, Some(DirectionDecoder { choice, ..stored }));
        println!("stored decoder with {choice:?}: {acc:.4}");
    }
    let (tuned, accuracy) = if per_stroke.1 > sequence.1 {
        per_stroke
    } else {
        sequence
    };
    println!(
        "{} validation items: stored {stored:?}: {:.4}; rules alone {:.4}; re-tuned {tuned:?}: {accuracy:.4}",
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
