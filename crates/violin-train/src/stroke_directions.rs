//! Stroke directions on labelled corpus items: what the analysis needs to decode them (bow
//! changes, notes, downbeats and the network's down-bow output), their accuracy against the
//! labelled strokes, and the choice of the direction decoder on validation items.
//!
//! Accuracy is counted per labelled stroke as `evaluate` counts it
//! ([`crate::evaluate::direction_tally`]): the decoded stroke sounding at the labelled
//! stroke's midpoint must have its direction.

use bowing_net::data::Recording;
use bowing_net::stroke::direction::{DirectionChoice, DirectionDecoder, LongRunStay};
use bowing_net::BowingModel;
use performance::{strokes_of, BowStroke, Note};
use rayon::prelude::*;

use crate::evaluate::{direction_tally, Tally};
use crate::Result;

/// One labelled item, analysed once: everything the direction decoding reads.
#[derive(Debug, Clone)]
pub struct DirectionCase {
    /// The model's bow changes, seconds.
    pub bow_changes_s: Vec<f64>,
    /// The analysis's notes.
    pub notes: Vec<Note>,
    /// The analysis's beats, seconds.
    pub beats_s: Vec<f64>,
    /// The analysis's downbeats, seconds.
    pub downbeats_s: Vec<f64>,
    /// The model's analysis (down-bow probabilities per frame included).
    pub bowed: bowing_net::stroke::StrokeAnalysis,
    /// The labelled strokes.
    pub truth: Vec<BowStroke>,
}

/// Analyses item `r` (audio `audio`) with `model` for the changes and the down-bow output
/// and with `pipeline` for notes and downbeats.
pub fn direction_case(
    r: &Recording,
    audio: &dsp_mel::Audio,
    model: &BowingModel,
    pipeline: &violin_skeleton::Pipeline,
) -> Result<DirectionCase> {
    let analysis = pipeline
        .analyze(audio)
        .map_err(|e| crate::TrainError::Dataset {
            path: r.name.clone().into(),
            reason: e.to_string(),
        })?;
    let bowed = model.analyze_mel(r.mel_db.view())?;
    Ok(DirectionCase {
        bow_changes_s: bowed.bow_changes_s.clone(),
        notes: analysis.notes,
        beats_s: analysis.beats_s,
        downbeats_s: analysis.downbeats_s,
        bowed,
        truth: r.strokes.clone(),
    })
}

/// Labelled strokes whose direction the decoding gets right, out of all labelled strokes, with
/// `decoder` (`None`: the bowing rules alone).
pub fn direction_accuracy(case: &DirectionCase, decoder: Option<DirectionDecoder>) -> Tally {
    let mut bowed = case.bowed.clone();
    bowed.direction_decoder = decoder;
    let dirs = bowed.directions(
        &case.bow_changes_s,
        &case.notes,
        &case.beats_s,
        &case.downbeats_s,
    );
    let predicted = strokes_of(&case.bow_changes_s, &dirs, &case.notes);
    direction_tally(&case.truth, &predicted)
}

/// Pooled accuracy over `cases`.
pub fn pooled_accuracy(cases: &[DirectionCase], decoder: Option<DirectionDecoder>) -> f64 {
    let mut pooled = Tally::default();
    for c in cases {
        pooled.add(&direction_accuracy(c, decoder));
    }
    pooled.share()
}

/// The decoder with the best pooled accuracy on `cases` (validation items only) over a
/// grid of network, rule, downbeat and beat weights, stay probabilities and both
/// [`DirectionChoice`]s (the sequence first, so it wins ties), and its accuracy; the rules
/// alone (`None`) when nothing beats them.
pub fn tune_direction_decoder(cases: &[DirectionCase]) -> (Option<DirectionDecoder>, f64) {
    tune_direction_decoder_with(cases, &[None], &BOTH_CHOICES)
}

/// Both [`DirectionChoice`]s, the sequence first.
pub const BOTH_CHOICES: [DirectionChoice; 2] = [
    DirectionChoice::MostProbableSequence,
    DirectionChoice::MostProbablePerStroke,
];

/// [`tune_direction_decoder`] with each of `long_runs` tried (`None`: one stay probability
/// for every change) and only the given `choices`.
pub fn tune_direction_decoder_with(
    cases: &[DirectionCase],
    long_runs: &[Option<LongRunStay>],
    choices: &[DirectionChoice],
) -> (Option<DirectionDecoder>, f64) {
    let mut grid = Vec::new();
    for &choice in choices {
        for &long in long_runs {
            for net_weight in [0.0f32, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0] {
                for rule_weight in [0.0f32, 0.25, 0.5, 1.0] {
                    for stay_probability in [0.02f32, 0.05, 0.1, 0.2] {
                        for downbeat_weight in [0.0f32, 1.0, 2.0, 3.0, 4.0] {
                            for beat_weight in [0.0f32, 0.3, 0.6, 1.0] {
                                grid.push(DirectionDecoder {
                                    net_weight,
                                    rule_weight,
                                    stay_probability,
                                    downbeat_weight,
                                    beat_weight,
                                    long_runs: long,
                                    choice,
                                });
                            }
                        }
                    }
                }
            }
        }
    }
    // Scored in parallel; the first best in grid order wins, as a sequential scan would.
    let scores: Vec<f64> = grid
        .par_iter()
        .map(|d| pooled_accuracy(cases, Some(*d)))
        .collect();
    let mut best = (None, pooled_accuracy(cases, None));
    for (d, acc) in grid.into_iter().zip(scores) {
        if acc > best.1 {
            best = (Some(d), acc);
        }
    }
    best
}
