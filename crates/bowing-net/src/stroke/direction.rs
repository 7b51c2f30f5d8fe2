//! Stroke directions from the network's down-bow output, the bars and the bowing rules,
//! decoded over all strokes at once.
//!
//! A two-state (down, up) hidden Markov model over the strokes: the direction flips at a
//! bow change, except with probability [`DirectionDecoder::stay_probability`] (a missed
//! change between two detected strokes, or a retake). Each stroke's evidence for a
//! direction adds up
//!
//! * the network's mean down-bow log-odds over the stroke's frames, weighted by
//!   [`DirectionDecoder::net_weight`];
//! * [`DirectionDecoder::rule_weight`] for the direction the bowing rules give it
//!   (`performance::heard_bow_directions`: a pickup up-bow, a retake to down-bow after a
//!   rest, a down-bow on a downbeat);
//! * for a down-bow, [`DirectionDecoder::downbeat_weight`] or
//!   [`DirectionDecoder::beat_weight`] when the stroke starts on a decoded downbeat or beat
//!   ([`beat_places`]): players plan their bowing so that bars start down-bow.
//!
//! Decoding all strokes together lets the bars put the bow back in phase after a missed
//! change instead of letting it flip the rest of the piece. The decoder reports either the
//! most probable sequence (Viterbi) or each stroke's most probable direction
//! (forward–backward; [`DirectionChoice`], the shipped weights' choice). The weights and
//! the choice are made on validation data and stored with the network's weights.

use performance::BowDirection;
use serde::{Deserialize, Serialize};

pub use super::direction_choice::DirectionChoice;
use super::direction_choice::{most_probable_per_stroke, most_probable_sequence};
use super::long_runs::keep_flip_log_probabilities;
pub use super::long_runs::LongRunStay;

/// How the direction sequence is decoded (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DirectionDecoder {
    /// Weight of the network's evidence (0: rules only).
    pub net_weight: f32,
    /// Log-bonus for the rules' direction.
    pub rule_weight: f32,
    /// Probability that a stroke keeps the previous stroke's direction.
    pub stay_probability: f32,
    /// Log-bonus for a down-bow on a stroke that starts on a downbeat (players plan their
    /// bowing so that bars start down-bow). 0 in files written before it existed.
    #[serde(default)]
    pub downbeat_weight: f32,
    /// Log-bonus for a down-bow on a stroke that starts on another beat.
    #[serde(default)]
    pub beat_weight: f32,
    /// Changes inside long runs of change probability keep the direction with their own
    /// probability (`None`: every change uses `stay_probability`). Absent from files
    /// written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub long_runs: Option<LongRunStay>,
    /// Whether the decoder reports the most probable sequence of directions (Viterbi) or
    /// each stroke's most probable direction (forward–backward). Absent from files written
    /// before it existed, which decode the sequence.
    #[serde(default, skip_serializing_if = "DirectionChoice::is_sequence")]
    pub choice: DirectionChoice,
}

/// Where a stroke starts in the bar, as heard: on a downbeat, on another beat, or between
/// beats (within [`performance::HEARD_ON_BEAT_S`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BeatPlace {
    /// On a downbeat.
    Downbeat,
    /// On a beat that is not a downbeat.
    Beat,
    /// Between beats.
    Between,
}

/// The [`BeatPlace`] of each of `starts_s` among sorted `beats_s` and `downbeats_s`.
///
/// ```
/// use bowing_net::stroke::direction::{beat_places, BeatPlace::*};
/// let places = beat_places(&[0.0, 0.52, 0.75, 1.96], &[0.0, 0.5, 1.0, 1.5, 2.0], &[0.0, 2.0]);
/// assert_eq!(places, vec![Downbeat, Beat, Between, Downbeat]);
/// ```
pub fn beat_places(starts_s: &[f64], beats_s: &[f64], downbeats_s: &[f64]) -> Vec<BeatPlace> {
    let tol = performance::HEARD_ON_BEAT_S;
    let near = |times: &[f64], t: f64| {
        let i = times.partition_point(|&x| x < t - tol);
        times.get(i).is_some_and(|&x| (x - t).abs() <= tol)
    };
    starts_s
        .iter()
        .map(|&t| {
            if near(downbeats_s, t) {
                BeatPlace::Downbeat
            } else if near(beats_s, t) {
                BeatPlace::Beat
            } else {
                BeatPlace::Between
            }
        })
        .collect()
}

impl Default for DirectionDecoder {
    /// The rules alone.
    fn default() -> Self {
        DirectionDecoder {
            net_weight: 0.0,
            rule_weight: 1.0,
            stay_probability: 0.05,
            downbeat_weight: 0.0,
            beat_weight: 0.0,
            long_runs: None,
            choice: DirectionChoice::MostProbableSequence,
        }
    }
}

/// Mean down-bow log-odds of `down` (per-frame probabilities) over frames `[a, b)` (0 for
/// an empty span or no output).
pub fn mean_log_odds(down: &[f32], a: usize, b: usize) -> f32 {
    let span = down.get(a..b.min(down.len())).unwrap_or(&[]);
    if span.is_empty() {
        return 0.0;
    }
    let sum: f32 = span
        .iter()
        .map(|&p| {
            let p = if p.is_finite() {
                p.clamp(1e-4, 1.0 - 1e-4)
            } else {
                0.5
            };
            (p / (1.0 - p)).ln()
        })
        .sum();
    sum / span.len() as f32
}

fn log_sigmoid(x: f32) -> f32 {
    -((-x).exp().ln_1p())
}

impl DirectionDecoder {
    /// Checks that every weight is finite and the stay probability lies strictly between
    /// 0 and 1 (a weights file could carry anything).
    ///
    /// ```
    /// use bowing_net::stroke::direction::DirectionDecoder;
    /// assert!(DirectionDecoder::default().validate().is_ok());
    /// let bad = DirectionDecoder { stay_probability: 1.5, ..Default::default() };
    /// assert!(bad.validate().unwrap_err().contains("stay_probability"));
    /// ```
    pub fn validate(&self) -> Result<(), String> {
        let weights = [
            ("net_weight", self.net_weight),
            ("rule_weight", self.rule_weight),
            ("downbeat_weight", self.downbeat_weight),
            ("beat_weight", self.beat_weight),
        ];
        if let Some((name, v)) = weights.iter().find(|(_, v)| !v.is_finite()) {
            return Err(format!(
                "direction decoder: {name} is {v}, not a finite number"
            ));
        }
        if !(self.stay_probability > 0.0 && self.stay_probability < 1.0) {
            return Err(format!(
                "direction decoder: stay_probability is {}, not strictly between 0 and 1",
                self.stay_probability
            ));
        }
        if let Some(long) = self.long_runs {
            if !(long.stay_probability > 0.0 && long.stay_probability < 1.0) {
                return Err(format!(
                    "direction decoder: long_runs.stay_probability is {}, not strictly between 0 and 1",
                    long.stay_probability
                ));
            }
            if !long.threshold.is_finite() {
                return Err(format!(
                    "direction decoder: long_runs.threshold is {}, not a finite number",
                    long.threshold
                ));
            }
        }
        Ok(())
    }

    /// The directions of strokes with mean down-bow log-odds `evidence` (one per stroke,
    /// [`mean_log_odds`]), the rules' directions `rules` (same length; extra entries of
    /// either are ignored) and where each stroke starts in the bar, `places` (missing
    /// entries count as [`BeatPlace::Between`]).
    ///
    /// ```
    /// use bowing_net::stroke::direction::DirectionDecoder;
    /// use performance::BowDirection::{Down, Up};
    /// let d = DirectionDecoder { net_weight: 1.0, rule_weight: 0.5, ..Default::default() };
    /// // The rules started on the wrong foot (a missed change); the network clearly hears
    /// // the first and third strokes as up-bows.
    /// let dirs = d.decode(&[-3.0, 0.0, -3.0, 0.0], &[Down, Up, Down, Up], &[]);
    /// assert_eq!(dirs, vec![Up, Down, Up, Down]);
    /// ```
    pub fn decode(
        &self,
        evidence: &[f32],
        rules: &[BowDirection],
        places: &[BeatPlace],
    ) -> Vec<BowDirection> {
        self.decode_with_flips(evidence, rules, places, &[])
    }

    /// The `(keep, flip)` log-probabilities of a change outside long runs.
    pub fn default_flip(&self) -> (f32, f32) {
        keep_flip_log_probabilities(self.stay_probability)
    }

    /// [`DirectionDecoder::decode`] with the log-probabilities `(keep, flip)` of the
    /// direction at each stroke's start given per stroke in `flips` (entry 0 is not read;
    /// missing entries use [`DirectionDecoder::stay_probability`]): a boundary that may not
    /// be a bow change at all can be given an even chance of flipping.
    ///
    /// ```
    /// use bowing_net::stroke::direction::DirectionDecoder;
    /// use performance::BowDirection::{Down, Up};
    /// let d = DirectionDecoder { net_weight: 1.0, rule_weight: 0.0, ..Default::default() };
    /// let even = (0.5f32.ln(), 0.5f32.ln());
    /// // The second boundary may or may not be a change: the evidence decides.
    /// let dirs = d.decode_with_flips(&[3.0, -3.0, -3.0], &[Down; 3], &[], &[even, even, even]);
    /// assert_eq!(dirs, vec![Down, Up, Up]);
    /// ```
    pub fn decode_with_flips(
        &self,
        evidence: &[f32],
        rules: &[BowDirection],
        places: &[BeatPlace],
        flips: &[(f32, f32)],
    ) -> Vec<BowDirection> {
        let emissions = self.emissions(evidence, rules, places);
        let default_flip = self.default_flip();
        let flip_at = |k: usize| flips.get(k).copied().unwrap_or(default_flip);
        let down = match self.choice {
            DirectionChoice::MostProbableSequence => most_probable_sequence(&emissions, flip_at),
            DirectionChoice::MostProbablePerStroke => most_probable_per_stroke(&emissions, flip_at),
        };
        down.into_iter()
            .map(|d| {
                if d {
                    BowDirection::Down
                } else {
                    BowDirection::Up
                }
            })
            .collect()
    }

    /// Each stroke's `[down, up]` log-score: the network's evidence, the rules' direction
    /// and the bonus for a down-bow where the stroke starts (one entry per stroke of the
    /// shorter of `evidence` and `rules`).
    fn emissions(
        &self,
        evidence: &[f32],
        rules: &[BowDirection],
        places: &[BeatPlace],
    ) -> Vec<[f32; 2]> {
        let n = evidence.len().min(rules.len());
        let emit = |k: usize, dir: BowDirection| -> f32 {
            let odds = if evidence[k].is_finite() {
                evidence[k]
            } else {
                0.0
            };
            let net = match dir {
                BowDirection::Down => log_sigmoid(odds),
                BowDirection::Up => log_sigmoid(-odds),
            };
            let rule = if rules[k] == dir {
                self.rule_weight
            } else {
                0.0
            };
            let place = match (dir, places.get(k)) {
                (BowDirection::Down, Some(BeatPlace::Downbeat)) => self.downbeat_weight,
                (BowDirection::Down, Some(BeatPlace::Beat)) => self.beat_weight,
                _ => 0.0,
            };
            self.net_weight * net + rule + place
        };
        (0..n)
            .map(|k| [emit(k, BowDirection::Down), emit(k, BowDirection::Up)])
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use BowDirection::{Down, Up};

    #[test]
    fn rules_alone_are_kept_and_evidence_corrects_a_wrong_start() {
        let rules = [Down, Up, Down, Down, Up];
        let alone = DirectionDecoder {
            net_weight: 0.0,
            rule_weight: 5.0,
            ..Default::default()
        };
        assert_eq!(alone.decode(&[0.0; 5], &rules, &[]), rules.to_vec());
        let heard = DirectionDecoder {
            net_weight: 1.0,
            rule_weight: 0.2,
            ..Default::default()
        };
        // Strong up-bow evidence on the first two strokes' alternation.
        let dirs = heard.decode(
            &[-4.0, 4.0, -4.0, 0.0, 0.0],
            &[Down, Up, Down, Up, Down],
            &[],
        );
        assert_eq!(dirs, vec![Up, Down, Up, Down, Up]);
        assert!(heard.decode(&[], &[], &[]).is_empty());
        assert_eq!(heard.decode(&[f32::NAN], &[Up], &[]), vec![Up]);
    }

    #[test]
    fn downbeats_put_the_bow_back_in_phase() {
        use BeatPlace::{Between, Downbeat};
        // Alternation with no rule or network evidence: the downbeats decide the phase.
        let bars = DirectionDecoder {
            net_weight: 0.0,
            rule_weight: 0.0,
            stay_probability: 0.05,
            downbeat_weight: 4.0,
            beat_weight: 0.0,
            ..Default::default()
        };
        // Both downbeats down costs one kept direction (a missed change) between them.
        let places = [Between, Downbeat, Between, Between, Downbeat];
        let dirs = bars.decode(&[0.0; 5], &[Down; 5], &places);
        assert_eq!((dirs[0], dirs[1], dirs[4]), (Up, Down, Down));
        let kept = dirs.windows(2).filter(|w| w[0] == w[1]).count();
        assert_eq!(kept, 1);
        // Without the downbeat weight the same cues give plain alternation.
        let plain = DirectionDecoder {
            downbeat_weight: 0.0,
            rule_weight: 0.5,
            ..bars
        };
        assert_eq!(
            plain.decode(&[0.0; 3], &[Down, Up, Down], &places),
            vec![Down, Up, Down]
        );
    }

    #[test]
    fn a_long_run_is_where_a_lost_change_goes_back() {
        use BeatPlace::{Between, Downbeat};
        // Four strokes; the changes at frames 4 and 7 were split from one long run of change
        // probability. The downbeats say strokes 0 and 3 are down-bows: three flips between
        // them cannot be right, so one change must keep the direction.
        let change = [
            0.9, 0.1, 0.1, 0.7, 0.8, 0.8, 0.8, 0.8, 0.8, 0.7, 0.1, 0.9, 0.1,
        ];
        let frames = [0usize, 4, 7, 11];
        let places = [Downbeat, Between, Between, Downbeat];
        let long = LongRunStay {
            min_frames: 5,
            threshold: 0.65,
            stay_probability: 0.3,
        };
        let d = DirectionDecoder {
            net_weight: 0.0,
            rule_weight: 0.0,
            stay_probability: 0.05,
            downbeat_weight: 4.0,
            beat_weight: 0.0,
            long_runs: Some(long),
            ..Default::default()
        };
        let flips = long.flips(&change, &frames, d.default_flip());
        assert_eq!(flips[0], d.default_flip());
        assert_eq!(flips[3], d.default_flip());
        assert!(flips[1..3].iter().all(|f| f.0 > d.default_flip().0));
        let dirs = d.decode_with_flips(&[0.0; 4], &[Down; 4], &places, &flips);
        assert_eq!((dirs[0], dirs[3]), (Down, Down));
        // The kept direction falls inside the run, not at the lone change at frame 11.
        let kept: Vec<usize> = (1..4).filter(|&k| dirs[k] == dirs[k - 1]).collect();
        assert_eq!(kept.len(), 1);
        assert!(kept[0] < 3, "{dirs:?}");
        // Invalid settings are refused by validate.
        let bad = DirectionDecoder {
            long_runs: Some(LongRunStay {
                stay_probability: 0.0,
                ..long
            }),
            ..d
        };
        assert!(bad
            .validate()
            .unwrap_err()
            .contains("long_runs.stay_probability"));
        assert!(!long.contains(&[], 0));
        assert!(!long.contains(&[f32::NAN; 8], 3));
    }

    #[test]
    fn mean_log_odds_of_spans() {
        let down = [0.9f32, 0.9, 0.1, 0.1];
        assert!(mean_log_odds(&down, 0, 2) > 2.0);
        assert!(mean_log_odds(&down, 2, 4) < -2.0);
        assert_eq!(mean_log_odds(&down, 3, 3), 0.0);
        assert_eq!(mean_log_odds(&down, 10, 20), 0.0);
        assert!(mean_log_odds(&[f32::NAN, 1.0], 0, 2).is_finite());
    }
}
