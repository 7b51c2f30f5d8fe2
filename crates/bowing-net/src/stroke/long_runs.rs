//! Changes inside long runs of change probability: where a direction decoder puts back a
//! bow change the change decoder lost or invented in fast strokes.

use serde::{Deserialize, Serialize};

/// Fast strokes: the change decoder guesses how many changes a long run of high change
/// probability holds ([`crate::RunSplit`]), and a wrong count flips every later stroke. A
/// change inside such a run keeps the previous direction with its own probability, so the
/// decoder puts a lost change back where one most likely went missing or was invented.
///
/// ```
/// use bowing_net::stroke::direction::LongRunStay;
/// let long = LongRunStay { min_frames: 5, threshold: 0.65, stay_probability: 0.2 };
/// let change = [0.1, 0.7, 0.8, 0.9, 0.8, 0.7, 0.1, 0.9, 0.1];
/// assert!(long.contains(&change, 3));   // inside the 5-frame run
/// assert!(!long.contains(&change, 7));  // a lone peak
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LongRunStay {
    /// A run of at least this many frames at or above `threshold` is long.
    pub min_frames: usize,
    /// The change probability the run's frames reach.
    pub threshold: f32,
    /// Probability that a change inside a long run keeps the previous direction.
    pub stay_probability: f32,
}

/// The `(keep, flip)` log-probabilities of a boundary that keeps the direction with
/// probability `stay` (clamped away from 0 and 1).
pub fn keep_flip_log_probabilities(stay: f32) -> (f32, f32) {
    let stay = stay.clamp(1e-6, 1.0 - 1e-6);
    (stay.ln(), (1.0 - stay).ln())
}

impl LongRunStay {
    /// Whether frame `frame` of the change probability `change` lies in a long run.
    pub fn contains(&self, change: &[f32], frame: usize) -> bool {
        let high = |i: usize| change.get(i).is_some_and(|&p| p >= self.threshold);
        if !high(frame) {
            return false;
        }
        let mut start = frame;
        while start > 0 && high(start - 1) {
            start -= 1;
        }
        let mut end = frame + 1;
        while high(end) {
            end += 1;
        }
        end - start >= self.min_frames
    }

    /// The `(keep, flip)` log-probabilities of the change at each of `frames`, for
    /// `DirectionDecoder::decode_with_flips`: this stay probability inside a long run,
    /// `default` elsewhere.
    pub fn flips(&self, change: &[f32], frames: &[usize], default: (f32, f32)) -> Vec<(f32, f32)> {
        let inside = keep_flip_log_probabilities(self.stay_probability);
        frames
            .iter()
            .map(|&f| {
                if self.contains(change, f) {
                    inside
                } else {
                    default
                }
            })
            .collect()
    }
}
