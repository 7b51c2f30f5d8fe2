//! Scores of the stroke network on labelled recordings (feature `train`): bow-change F1
//! (±2 frames) and per-frame string accuracy.

use serde::{Deserialize, Serialize};

use super::decode::changes_inside;
use super::{played, stroke_input, FrameOutputs, StrokeDetector};
use crate::data::Recording;
use crate::decode::Decoder;
use crate::error::Result;
use crate::metrics::{match_events, tune_decoder, Counts};

/// Scores over a set of recordings (pooled).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct StrokeScores {
    /// Bow changes matched within ±2 frames.
    pub changes: Counts,
    /// Frames with a sounding note whose most probable string is right.
    pub string_frames_correct: usize,
    /// Frames with a sounding note and a known string.
    pub string_frames: usize,
}

impl StrokeScores {
    /// Bow-change F1.
    pub fn change_f1(&self) -> f64 {
        self.changes.f1()
    }

    /// Fraction of sounding frames with the right string (0 when there are none).
    pub fn string_accuracy(&self) -> f64 {
        ratio(self.string_frames_correct, self.string_frames)
    }

    /// What training maximises: change F1 + string accuracy.
    pub fn selection_score(&self) -> f64 {
        self.change_f1() + self.string_accuracy()
    }

    /// Adds another set's counts.
    pub fn add(&mut self, o: &StrokeScores) {
        self.changes.add(&o.changes);
        self.string_frames_correct += o.string_frames_correct;
        self.string_frames += o.string_frames;
    }
}

fn ratio(a: usize, b: usize) -> f64 {
    if b == 0 {
        0.0
    } else {
        a as f64 / b as f64
    }
}

/// Scores one recording from its frame outputs, played stretches and decoder.
pub fn score_recording(
    r: &Recording,
    out: &FrameOutputs,
    stretches: &[(usize, usize)],
    decoder: &Decoder,
) -> StrokeScores {
    let mut s = StrokeScores::default();
    let fractional = changes_inside(&decoder.pick_fractional(&out.change), stretches);
    let picked: Vec<usize> = fractional.iter().map(|f| f.round() as usize).collect();
    s.changes.add(&match_events(&picked, &r.changes, 2));
    for (f, &string) in r.strings.iter().enumerate() {
        let Some(p) = out.string.get(f) else { break };
        if !(1..=4).contains(&string) {
            continue;
        }
        s.string_frames += 1;
        let best = (0..4).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap_or(0);
        if best + 1 == usize::from(string) {
            s.string_frames_correct += 1;
        }
    }
    s
}

/// Runs `detector` on every recording and scores it; with `decoder = None` the decoder is
/// first tuned on these recordings (use only on validation data) and returned.
pub fn score_recordings(
    detector: &StrokeDetector,
    recordings: &[Recording],
    decoder: Option<Decoder>,
) -> Result<(StrokeScores, Decoder)> {
    let mut outputs = Vec::with_capacity(recordings.len());
    for r in recordings {
        let input = stroke_input(r.mel_db.view());
        let out = detector.net().frame_outputs(&input)?;
        outputs.push((out, played(&input)));
    }
    let decoder = decoder.unwrap_or_else(|| {
        let probs: Vec<Vec<f32>> = outputs.iter().map(|(o, _)| o.change.clone()).collect();
        tune_decoder(&probs, recordings).0
    });
    let mut total = StrokeScores::default();
    for (r, (out, stretches)) in recordings.iter().zip(&outputs) {
        total.add(&score_recording(r, out, stretches, &decoder));
    }
    Ok((total, decoder))
}
