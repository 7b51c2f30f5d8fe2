//! [`BowStroke`]: one stroke of the bow, its direction ([`BowDirection`]) and the string it
//! plays.

use fingering::ViolinString;

use crate::bowing::BowDirection;
use serde::{Deserialize, Serialize};

/// One bow stroke: from a bow change (or the first note after a rest) to the next, with its
/// direction and the string of its first note (`None` when the note has no fingering).
///
/// ```
/// use performance::{BowDirection, BowStroke};
/// let s = BowStroke { start_s: 0.5, end_s: 1.0, direction: BowDirection::Down, string: None };
/// assert_eq!(s.direction.reversed(), BowDirection::Up);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BowStroke {
    /// Onset of the stroke's first note, seconds.
    pub start_s: f64,
    /// End of the stroke's last note, seconds.
    pub end_s: f64,
    /// Down or up.
    pub direction: BowDirection,
    /// The string of the stroke's first note.
    pub string: Option<ViolinString>,
}

/// The strokes that bow changes and their directions make over `notes` (sorted by onset):
/// stroke `k` starts at `bow_changes_s[k]` with `directions[k]`, ends where the last note
/// starting before the next change ends (or at the next change when no note starts in
/// between), and takes the string of its first note (the first note starting within 50 ms
/// before the change or later). Extra changes or directions beyond the shorter list are
/// ignored.
///
/// ```
/// use performance::{strokes_of, BowDirection, Note};
/// let notes = [Note::new(0.0, 0.5, 67), Note::new(0.5, 1.0, 69), Note::new(1.0, 2.0, 71)];
/// let s = strokes_of(&[0.0, 1.0], &[BowDirection::Down, BowDirection::Up], &notes);
/// assert_eq!((s[0].start_s, s[0].end_s), (0.0, 1.0));
/// assert_eq!((s[1].start_s, s[1].end_s, s[1].direction), (1.0, 2.0, BowDirection::Up));
/// ```
pub fn strokes_of(
    bow_changes_s: &[f64],
    directions: &[BowDirection],
    notes: &[crate::Note],
) -> Vec<BowStroke> {
    const EARLY_S: f64 = 0.05;
    let n = bow_changes_s.len().min(directions.len());
    (0..n)
        .map(|k| {
            let start_s = bow_changes_s[k];
            let next = bow_changes_s.get(k + 1).copied().unwrap_or(f64::INFINITY);
            let first = notes.partition_point(|x| x.onset_s < start_s - EARLY_S);
            let inside = notes[first..].partition_point(|x| x.onset_s < next - EARLY_S);
            let end_s = notes[first..first + inside]
                .iter()
                .map(|x| x.offset_s)
                .fold(f64::NEG_INFINITY, f64::max);
            let end_s = if end_s.is_finite() {
                end_s.max(start_s)
            } else if next.is_finite() {
                next
            } else {
                start_s
            };
            BowStroke {
                start_s,
                end_s,
                direction: directions[k],
                string: notes
                    .get(first)
                    .filter(|_| inside > 0)
                    .and_then(|x| x.fingering)
                    .map(|f| f.string),
            }
        })
        .collect()
}
