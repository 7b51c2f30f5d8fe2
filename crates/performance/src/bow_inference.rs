//! Stroke directions of a *detected* bowing: like [`crate::bow_directions`], but robust to
//! a missed or an extra bow change.
//!
//! [`crate::bow_directions`] alternates strictly, so one missed change in an analysis
//! flips every later stroke of the phrase. [`infer_bow_directions`] instead finds the most
//! probable direction sequence (Viterbi over down/up per stroke):
//! * a change usually flips the direction (a stroke keeping it costs `ln 0.1`: the trace of
//!   a change that was missed or invented);
//! * after a rest of at least [`crate::RETAKE_REST_S`] the bow may be retaken: keeping the
//!   direction costs only `ln 0.4` (`ln 0.6` to flip);
//! * a stroke starting on a downbeat (±70 ms) is a down-bow with probability 0.75.

use crate::bowing::{BowDirection, RETAKE_REST_S};
use crate::note::Note;

const KEEP: f64 = 0.1;
const RETAKE: f64 = 0.4;
const DOWN_ON_DOWNBEAT: f64 = 0.75;
const ON_DOWNBEAT_S: f64 = 0.07;

/// One direction per bow change (module docs); `notes` tell where the rests are.
///
/// ```
/// use performance::{infer_bow_directions, BowDirection::{Down, Up}, Note};
/// let notes: Vec<Note> = (0..8).map(|k| Note::new(0.5 * k as f64, 0.5 * (k + 1) as f64, 67)).collect();
/// // A change at 1.5 s was missed: the strokes at 2.0 and 3.0 start bars.
/// let changes = [0.0, 0.5, 1.0, 2.0, 2.5, 3.0, 3.5];
/// let dirs = infer_bow_directions(&changes, &notes, &[0.0, 1.0, 2.0, 3.0]);
/// assert_eq!(dirs[3], Down);
/// assert_eq!(dirs[5], Down);
/// ```
pub fn infer_bow_directions(
    bow_changes_s: &[f64],
    notes: &[Note],
    downbeats_s: &[f64],
) -> Vec<BowDirection> {
    let n = bow_changes_s.len();
    if n == 0 {
        return Vec::new();
    }
    let on_downbeat = |t: f64| {
        let i = downbeats_s.partition_point(|&d| d < t - ON_DOWNBEAT_S);
        downbeats_s
            .get(i)
            .is_some_and(|&d| (d - t).abs() <= ON_DOWNBEAT_S)
    };
    let mut sounding_until = Vec::with_capacity(notes.len());
    let mut latest = f64::NEG_INFINITY;
    for note in notes {
        latest = latest.max(note.offset_s);
        sounding_until.push((note.onset_s, latest));
    }
    let rest_before = |t: f64| {
        let i = sounding_until.partition_point(|&(on, _)| on < t - 1e-6);
        match i.checked_sub(1).and_then(|k| sounding_until.get(k)) {
            Some(&(_, until)) => t - until >= RETAKE_REST_S,
            None => true,
        }
    };
    let emit = |t: f64| -> [f64; 2] {
        if on_downbeat(t) {
            [DOWN_ON_DOWNBEAT.ln(), (1.0 - DOWN_ON_DOWNBEAT).ln()]
        } else {
            [0.0, 0.0]
        }
    };
    let (keep, flip) = (KEEP.ln(), (1.0 - KEEP).ln());
    // State 0 = down, 1 = up; ties prefer down.
    let mut score = emit(bow_changes_s[0]);
    score[1] -= 1e-9;
    let mut back = vec![[0usize; 2]; n];
    for (k, &t) in bow_changes_s.iter().enumerate().skip(1) {
        let free = rest_before(t);
        let e = emit(t);
        let mut next = [f64::NEG_INFINITY; 2];
        for (to, slot) in next.iter_mut().enumerate() {
            for (from, &prev) in score.iter().enumerate() {
                let step = if free {
                    if from == to {
                        RETAKE.ln()
                    } else {
                        (1.0 - RETAKE).ln()
                    }
                } else if from == to {
                    keep
                } else {
                    flip
                };
                let v = prev + step + e[to];
                if v > *slot {
                    *slot = v;
                    back[k][to] = from;
                }
            }
        }
        score = next;
    }
    let mut state = usize::from(score[1] > score[0]);
    let mut out = vec![BowDirection::Down; n];
    for k in (0..n).rev() {
        out[k] = if state == 0 {
            BowDirection::Down
        } else {
            BowDirection::Up
        };
        state = back[k][state];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use BowDirection::{Down, Up};

    #[test]
    fn alternates_and_follows_pickups_and_retakes() {
        let notes: Vec<Note> = [(0.5, 1.0), (1.0, 1.5), (3.0, 3.5), (3.5, 4.0)]
            .iter()
            .map(|&(a, b)| Note::new(a, b, 67))
            .collect();
        let changes: Vec<f64> = notes.iter().map(|n| n.onset_s).collect();
        assert_eq!(
            infer_bow_directions(&changes, &notes, &[1.0, 3.0]),
            vec![Up, Down, Down, Up]
        );
        assert_eq!(
            infer_bow_directions(&changes, &notes, &[]),
            vec![Down, Up, Down, Up]
        );
        assert!(infer_bow_directions(&[], &notes, &[1.0]).is_empty());
    }
}
