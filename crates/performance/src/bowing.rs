//! Stroke directions: which bow changes start a down-bow and which an up-bow.

use serde::{Deserialize, Serialize};

use crate::note::Note;

/// A stroke's direction: down-bow (frog to tip) or up-bow (tip to frog).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BowDirection {
    /// Frog to tip.
    Down,
    /// Tip to frog.
    Up,
}

impl BowDirection {
    /// +1 for down (the bow position, frog 0 → tip 1, increases), −1 for up.
    pub fn sign(self) -> f64 {
        match self {
            BowDirection::Down => 1.0,
            BowDirection::Up => -1.0,
        }
    }

    /// The other direction.
    pub fn reversed(self) -> BowDirection {
        match self {
            BowDirection::Down => BowDirection::Up,
            BowDirection::Up => BowDirection::Down,
        }
    }
}

/// A rest at least this long (seconds) before a stroke lets the player lift and retake the
/// bow.
pub const RETAKE_REST_S: f64 = 0.5;
/// A stroke starts "on" a downbeat within this many seconds of it.
const ON_BEAT_S: f64 = 0.05;

/// The direction of each stroke, one per entry of `bow_changes_s` (sorted), from the
/// notes' timing and the bars — the same rules for audio and MIDI analysis:
///
/// 1. the bow alternates: each stroke reverses the previous one;
/// 2. the first stroke is a down-bow, unless it is a pickup (it starts before the first
///    downbeat and the next stroke starts on that downbeat), which is an up-bow so that
///    the bar starts down;
/// 3. after a rest of at least [`RETAKE_REST_S`] (no note sounding), a stroke that starts
///    on a downbeat is a down-bow (the player lifts the bow and retakes it at the frog).
pub fn bow_directions(
    bow_changes_s: &[f64],
    notes: &[Note],
    downbeats_s: &[f64],
) -> Vec<BowDirection> {
    let on_downbeat = |t: f64| {
        let i = downbeats_s.partition_point(|&d| d < t - ON_BEAT_S);
        downbeats_s
            .get(i)
            .is_some_and(|&d| (d - t).abs() <= ON_BEAT_S)
    };
    // Latest offset of the notes that start before t (notes sorted by onset).
    let mut sounding_until = Vec::with_capacity(notes.len());
    let mut latest = f64::NEG_INFINITY;
    for n in notes {
        latest = latest.max(n.offset_s);
        sounding_until.push((n.onset_s, latest));
    }
    let rest_before = |t: f64| {
        let i = sounding_until.partition_point(|&(on, _)| on < t - 1e-6);
        match i.checked_sub(1).and_then(|k| sounding_until.get(k)) {
            Some(&(_, until)) => t - until >= RETAKE_REST_S,
            None => true,
        }
    };
    let mut out = Vec::with_capacity(bow_changes_s.len());
    for (k, &t) in bow_changes_s.iter().enumerate() {
        let direction = match out.last() {
            None => {
                let pickup = downbeats_s.first().is_some_and(|&d| t < d - ON_BEAT_S)
                    && bow_changes_s.get(1).is_some_and(|&next| on_downbeat(next));
                if pickup {
                    BowDirection::Up
                } else {
                    BowDirection::Down
                }
            }
            Some(&previous) => {
                if k > 0 && rest_before(t) && on_downbeat(t) {
                    BowDirection::Down
                } else {
                    BowDirection::reversed(previous)
                }
            }
        };
        out.push(direction);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use BowDirection::{Down, Up};

    #[test]
    fn alternate_pickup_and_retake() {
        let notes: Vec<Note> = [(0.5, 1.0), (1.0, 1.5), (3.0, 3.5), (3.5, 4.0)]
            .iter()
            .map(|&(a, b)| Note::new(a, b, 67))
            .collect();
        let changes: Vec<f64> = notes.iter().map(|n| n.onset_s).collect();
        let downbeats = [1.0, 3.0];
        // Pickup up, downbeat down; the rest 1.5..3.0 ends on a downbeat: retake, down again.
        assert_eq!(
            bow_directions(&changes, &notes, &downbeats),
            vec![Up, Down, Down, Up]
        );
        // Without bars: plain alternation from a down-bow.
        assert_eq!(
            bow_directions(&changes, &notes, &[]),
            vec![Down, Up, Down, Up]
        );
        assert!(bow_directions(&[], &notes, &downbeats).is_empty());
    }
}
