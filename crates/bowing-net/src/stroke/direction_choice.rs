//! How a direction decoder turns its two-state model into one direction per stroke: the
//! most probable sequence (Viterbi), or each stroke's most probable direction (posterior
//! marginals by forward–backward).
//!
//! The two differ where the model is unsure where the bow's phase breaks. Between two
//! downbeats that both want a down-bow, an odd number of detected changes means one change
//! was missed or invented; every placement of the kept direction scores the same, Viterbi
//! takes one end, and every stroke up to the other end is wrong when it guessed the wrong
//! end. The posterior weighs all placements, so the strokes near either downbeat follow
//! that downbeat: fewer strokes are wrong in expectation, which is what the per-stroke
//! accuracy counts.

use serde::{Deserialize, Serialize};

/// Which directions a [`super::direction::DirectionDecoder`] reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DirectionChoice {
    /// The most probable sequence of directions (Viterbi): consistent, every change a flip
    /// unless the model keeps the direction there.
    #[default]
    MostProbableSequence,
    /// Each stroke's most probable direction under the model (forward–backward): the most
    /// strokes right in expectation; two neighbours may share a direction where the model
    /// is unsure which change is missing.
    MostProbablePerStroke,
}

impl DirectionChoice {
    /// Whether this is the default, [`DirectionChoice::MostProbableSequence`] (not written
    /// to weights files, which then read as before it existed).
    pub fn is_sequence(&self) -> bool {
        *self == DirectionChoice::MostProbableSequence
    }
}

/// Viterbi over `[down, up]` log-scores per stroke, with the `(keep, flip)`
/// log-probabilities of the boundary before stroke `k` from `flip_at(k)`. `true` = down.
/// Ties go to the state that keeps the direction, then to down.
pub(crate) fn most_probable_sequence(
    emissions: &[[f32; 2]],
    flip_at: impl Fn(usize) -> (f32, f32),
) -> Vec<bool> {
    let Some(first) = emissions.first() else {
        return Vec::new();
    };
    let mut score = *first;
    let mut back: Vec<[u8; 2]> = Vec::with_capacity(emissions.len());
    back.push([0, 1]);
    for (k, emit) in emissions.iter().enumerate().skip(1) {
        let (log_stay, log_flip) = flip_at(k);
        let mut next = [0.0f32; 2];
        let mut from = [0u8; 2];
        for s in 0..2 {
            let via_same = score[s] + log_stay;
            let via_other = score[1 - s] + log_flip;
            (next[s], from[s]) = if via_same >= via_other {
                (via_same, s as u8)
            } else {
                (via_other, (1 - s) as u8)
            };
            next[s] += emit[s];
        }
        score = next;
        back.push(from);
    }
    let mut s = usize::from(score[1] > score[0]);
    let mut out = vec![true; emissions.len()];
    for k in (0..emissions.len()).rev() {
        out[k] = s == 0;
        s = usize::from(back[k][s]);
    }
    out
}

/// `ln(e^a + e^b)` without overflow.
fn log_add(a: f64, b: f64) -> f64 {
    let (hi, lo) = if a >= b { (a, b) } else { (b, a) };
    if hi == f64::NEG_INFINITY {
        return hi;
    }
    hi + (lo - hi).exp().ln_1p()
}

/// Each stroke's most probable direction (`true` = down) under the same model as
/// [`most_probable_sequence`], from forward–backward posterior marginals (in f64 so long
/// recordings do not lose precision). Ties go to down.
pub(crate) fn most_probable_per_stroke(
    emissions: &[[f32; 2]],
    flip_at: impl Fn(usize) -> (f32, f32),
) -> Vec<bool> {
    let n = emissions.len();
    if n == 0 {
        return Vec::new();
    }
    let step = |k: usize| {
        let (stay, flip) = flip_at(k);
        (f64::from(stay), f64::from(flip))
    };
    let emit = |k: usize, s: usize| f64::from(emissions[k][s]);
    let mut forward = vec![[0.0f64; 2]; n];
    forward[0] = [emit(0, 0), emit(0, 1)];
    for k in 1..n {
        let (stay, flip) = step(k);
        let prev = forward[k - 1];
        for s in 0..2 {
            forward[k][s] = log_add(prev[s] + stay, prev[1 - s] + flip) + emit(k, s);
        }
    }
    let mut backward = vec![[0.0f64; 2]; n];
    for k in (0..n - 1).rev() {
        let (stay, flip) = step(k + 1);
        let next = backward[k + 1];
        for s in 0..2 {
            backward[k][s] = log_add(
                stay + emit(k + 1, s) + next[s],
                flip + emit(k + 1, 1 - s) + next[1 - s],
            );
        }
    }
    (0..n)
        .map(|k| forward[k][0] + backward[k][0] >= forward[k][1] + backward[k][1])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flips(stay: f32) -> impl Fn(usize) -> (f32, f32) {
        move |_| (stay.ln(), (1.0 - stay).ln())
    }

    #[test]
    fn a_parity_break_costs_fewer_strokes_per_stroke() {
        // Eight strokes, the first and the last on a downbeat (a strong down-bow bonus):
        // seven changes between them cannot all flip, so one keeps the direction, and
        // nothing says which.
        let mut emissions = vec![[0.0f32, 0.0]; 8];
        emissions[0] = [4.0, 0.0];
        emissions[7] = [4.0, 0.0];
        let sequence = most_probable_sequence(&emissions, flips(0.05));
        let per_stroke = most_probable_per_stroke(&emissions, flips(0.05));
        assert!(sequence[0] && sequence[7]);
        assert!(per_stroke[0] && per_stroke[7]);
        // Viterbi keeps the direction at one end, so the strokes next to one of the
        // downbeats are all off by one; the posterior follows the nearer downbeat on
        // each side: the neighbours of both downbeats are up-bows.
        assert_eq!(sequence.windows(2).filter(|w| w[0] == w[1]).count(), 1);
        assert!(sequence[1] || sequence[6], "{sequence:?}");
        assert!(!per_stroke[1] && !per_stroke[6], "{per_stroke:?}");
    }

    #[test]
    fn files_without_a_choice_decode_the_sequence() {
        use crate::stroke::direction::DirectionDecoder;
        let old = r#"{"net_weight":1.0,"rule_weight":0.0,"stay_probability":0.02}"#;
        let d: DirectionDecoder = serde_json::from_str(old).unwrap();
        assert_eq!(d.choice, DirectionChoice::MostProbableSequence);
        // The default is not written, so such a file reads back the same.
        assert!(!serde_json::to_string(&d).unwrap().contains("choice"));
        let per_stroke = DirectionDecoder {
            choice: DirectionChoice::MostProbablePerStroke,
            ..d
        };
        let text = serde_json::to_string(&per_stroke).unwrap();
        assert!(
            text.contains(r#""choice":"most_probable_per_stroke""#),
            "{text}"
        );
        assert_eq!(
            serde_json::from_str::<DirectionDecoder>(&text).unwrap(),
            per_stroke
        );
    }

    #[test]
    fn both_agree_when_the_evidence_is_consistent_and_handle_empty_input() {
        let emissions: Vec<[f32; 2]> = (0..9)
            .map(|k| if k % 2 == 0 { [2.0, 0.0] } else { [0.0, 2.0] })
            .collect();
        let expected: Vec<bool> = (0..9).map(|k| k % 2 == 0).collect();
        assert_eq!(most_probable_sequence(&emissions, flips(0.05)), expected);
        assert_eq!(most_probable_per_stroke(&emissions, flips(0.05)), expected);
        assert!(most_probable_per_stroke(&[], flips(0.05)).is_empty());
        assert!(most_probable_sequence(&[], flips(0.05)).is_empty());
        // A long recording stays finite.
        let long = vec![[0.3f32, -0.2]; 200_000];
        assert_eq!(most_probable_per_stroke(&long, flips(0.02)).len(), 200_000);
        assert!(log_add(f64::NEG_INFINITY, f64::NEG_INFINITY).is_infinite());
    }
}
