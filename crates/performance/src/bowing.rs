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
/// A heard bow change (from audio) starts "on" a heard downbeat within this many seconds
/// of it: both are found within a few frames of the truth.
pub const HEARD_ON_BEAT_S: f64 = 0.1;

/// A hooked stroke (two strokes joined so that the next bar starts down-bow) is at most
/// this long (seconds).
pub const MAX_HOOKED_STROKE_S: f64 = 2.5;

/// The timing facts the direction rules read: downbeats and when notes sound.
struct DirectionRules<'a> {
    downbeats_s: &'a [f64],
    on_beat_s: f64,
    /// (onset, latest offset of the notes starting at or before it), by onset.
    sounding_until: Vec<(f64, f64)>,
}

impl<'a> DirectionRules<'a> {
    fn new(notes: &[Note], downbeats_s: &'a [f64], on_beat_s: f64) -> Self {
        let mut sounding_until = Vec::with_capacity(notes.len());
        let mut latest = f64::NEG_INFINITY;
        for n in notes {
            latest = latest.max(n.offset_s);
            sounding_until.push((n.onset_s, latest));
        }
        DirectionRules {
            downbeats_s,
            on_beat_s,
            sounding_until,
        }
    }

    fn on_downbeat(&self, t: f64) -> bool {
        let i = self
            .downbeats_s
            .partition_point(|&d| d < t - self.on_beat_s);
        self.downbeats_s
            .get(i)
            .is_some_and(|&d| (d - t).abs() <= self.on_beat_s)
    }

    /// The silence (s) before `t` since the last note starting before it stopped sounding
    /// (infinite before the first note).
    fn rest_before_s(&self, t: f64) -> f64 {
        let i = self
            .sounding_until
            .partition_point(|&(on, _)| on < t - 1e-6);
        match i.checked_sub(1).and_then(|k| self.sounding_until.get(k)) {
            Some(&(_, until)) => t - until,
            None => f64::INFINITY,
        }
    }

    /// The direction of each stroke of `bow_changes_s`, by [`Self::direction`]; with
    /// `downbeats_down`, every stroke after the first that starts on a downbeat is a
    /// down-bow.
    fn directions(&self, bow_changes_s: &[f64], downbeats_down: bool) -> Vec<BowDirection> {
        let mut out: Vec<BowDirection> = Vec::with_capacity(bow_changes_s.len());
        for (k, &t) in bow_changes_s.iter().enumerate() {
            let direction = match out.last() {
                Some(_) if downbeats_down && self.on_downbeat(t) => BowDirection::Down,
                previous => self.direction(previous.copied(), t, bow_changes_s.get(k + 1).copied()),
            };
            out.push(direction);
        }
        out
    }

    /// The direction of the stroke starting at `t` after one of direction `previous`
    /// (`None` for the first stroke, whose successor starts at `next`).
    fn direction(&self, previous: Option<BowDirection>, t: f64, next: Option<f64>) -> BowDirection {
        match previous {
            None => {
                let pickup = self
                    .downbeats_s
                    .first()
                    .is_some_and(|&d| t < d - self.on_beat_s)
                    && next.is_some_and(|next| self.on_downbeat(next));
                if pickup {
                    BowDirection::Up
                } else {
                    BowDirection::Down
                }
            }
            Some(previous) => {
                if self.rest_before_s(t) >= RETAKE_REST_S && self.on_downbeat(t) {
                    BowDirection::Down
                } else {
                    previous.reversed()
                }
            }
        }
    }
}

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
    DirectionRules::new(notes, downbeats_s, ON_BEAT_S).directions(bow_changes_s, false)
}

/// The directions of heard strokes (bow changes and downbeats found in audio): the rules
/// of [`bow_directions`], with a downbeat within [`HEARD_ON_BEAT_S`], plus
///
/// 4. a stroke that starts on a downbeat is a down-bow: players hook strokes so that bars
///    start down-bow ([`hooks_for_downbeats`]), so an up-bow there more likely follows a
///    bow change missed or invented by the detector, and the rule puts the bow back in
///    phase at every bar instead of carrying the error to the end.
///
/// ```
/// use performance::{heard_bow_directions, BowDirection::{Down, Up}, Note};
/// let onsets = [0.0, 0.5, 1.0, 1.5, 2.02];
/// let notes: Vec<Note> = onsets.iter().map(|&t| Note::new(t, t + 0.5, 67)).collect();
/// // The change at 1.0 s was not heard: alternation alone would start the bar at 2 s
/// // up-bow; the rule starts it down-bow, as played.
/// let heard = [0.0, 0.5, 1.5, 2.02];
/// assert_eq!(heard_bow_directions(&heard, &notes, &[0.0, 2.0]), vec![Down, Up, Down, Down]);
/// ```
pub fn heard_bow_directions(
    bow_changes_s: &[f64],
    notes: &[Note],
    downbeats_s: &[f64],
) -> Vec<BowDirection> {
    DirectionRules::new(notes, downbeats_s, HEARD_ON_BEAT_S).directions(bow_changes_s, true)
}

/// The bow changes a player drops ("hooks": plays two strokes in one bow) so that a bar
/// starts down-bow, as indices into `bow_changes_s` (sorted).
///
/// Walking the strokes with the rules of [`bow_directions`], wherever a stroke starting
/// on a downbeat would be an up-bow, the change before it is dropped when `may_hook`
/// agrees (called once per such place, so a caller can play some bars up-bow) and the
/// hook is playable: that change is neither the first nor on a downbeat, follows the
/// sound with less than [`RETAKE_REST_S`] of rest, and the joined stroke lasts at most
/// [`MAX_HOOKED_STROKE_S`].
///
/// ```
/// use performance::{bow_directions, hooks_for_downbeats, Note};
/// // Three strokes per bar would start every other bar up-bow.
/// let onsets: Vec<f64> = (0..7).map(|i| f64::from(i) / 3.0).collect();
/// let notes: Vec<Note> = onsets.iter().map(|&t| Note::new(t, t + 0.3, 67)).collect();
/// let bars = [0.0, 1.0, 2.0];
/// let hooks = hooks_for_downbeats(&onsets, &notes, &bars, |_| true);
/// assert_eq!(hooks, vec![2, 5]); // the notes at 0.67 s and 1.67 s are slurred on
/// let kept: Vec<f64> = onsets.iter().enumerate()
///     .filter(|(i, _)| !hooks.contains(i)).map(|(_, &t)| t).collect();
/// let dirs = bow_directions(&kept, &notes, &bars);
/// assert_eq!(dirs[2], performance::BowDirection::Down); // the stroke at 1.0 s
/// assert_eq!(dirs[4], performance::BowDirection::Down); // the stroke at 2.0 s
/// ```
pub fn hooks_for_downbeats(
    bow_changes_s: &[f64],
    notes: &[Note],
    downbeats_s: &[f64],
    mut may_hook: impl FnMut(usize) -> bool,
) -> Vec<usize> {
    let rules = DirectionRules::new(notes, downbeats_s, ON_BEAT_S);
    let mut hooks = Vec::new();
    // (index, start, direction) of the last two kept strokes.
    let mut last: Option<(usize, f64, BowDirection)> = None;
    let mut before_last: Option<(usize, f64, BowDirection)> = None;
    for (k, &t) in bow_changes_s.iter().enumerate() {
        let next = bow_changes_s.get(k + 1).copied();
        let mut direction = rules.direction(last.map(|l| l.2), t, next);
        if direction == BowDirection::Up && rules.on_downbeat(t) {
            if let (Some((i, start, _)), Some((_, from, earlier))) = (last, before_last) {
                let playable = !rules.on_downbeat(start)
                    && rules.rest_before_s(start) < RETAKE_REST_S
                    && t - from <= MAX_HOOKED_STROKE_S;
                if playable && may_hook(k) {
                    hooks.push(i);
                    // The joined stroke becomes the one before this.
                    last = before_last;
                    direction = rules.direction(Some(earlier), t, next);
                }
            }
        }
        before_last = last;
        last = Some((k, t, direction));
    }
    hooks
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

    #[test]
    fn hooks_start_bars_down_and_respect_the_limits() {
        // Three separate strokes per bar: alternation alone starts every other bar up-bow.
        let onsets: Vec<f64> = (0..12).map(|i| f64::from(i) * 0.3).collect();
        let notes: Vec<Note> = onsets.iter().map(|&t| Note::new(t, t + 0.3, 67)).collect();
        let downbeats = [0.0, 0.9, 1.8, 2.7];
        let ups_on_downbeats = |changes: &[f64]| {
            let dirs = bow_directions(changes, &notes, &downbeats);
            changes
                .iter()
                .zip(&dirs)
                .filter(|(t, d)| **d == Up && downbeats.iter().any(|b| (*b - **t).abs() < 0.01))
                .count()
        };
        assert_eq!(ups_on_downbeats(&onsets), 2);
        let hooks = hooks_for_downbeats(&onsets, &notes, &downbeats, |_| true);
        let kept: Vec<f64> = onsets
            .iter()
            .enumerate()
            .filter(|(i, _)| !hooks.contains(i))
            .map(|(_, &t)| t)
            .collect();
        assert!(!hooks.is_empty());
        assert_eq!(ups_on_downbeats(&kept), 0);
        // A player who never hooks, and strokes too long to join, keep every change.
        assert!(hooks_for_downbeats(&onsets, &notes, &downbeats, |_| false).is_empty());
        let slow: Vec<f64> = onsets.iter().map(|t| t * 10.0).collect();
        let slow_notes: Vec<Note> = slow.iter().map(|&t| Note::new(t, t + 3.0, 67)).collect();
        let slow_bars: Vec<f64> = downbeats.iter().map(|t| t * 10.0).collect();
        assert!(hooks_for_downbeats(&slow, &slow_notes, &slow_bars, |_| true).is_empty());
    }
}
