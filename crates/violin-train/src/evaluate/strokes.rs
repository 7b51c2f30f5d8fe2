//! Stroke directions and bowed strings of an analysis against a corpus's labelled strokes
//! and notes.

use std::path::Path;

use performance::BowStroke;
use serde::{Deserialize, Serialize};

use crate::Result;

/// What a corpus item says about its bowing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StrokeReferences {
    /// Labelled bow strokes (`strokes.tsv`; empty when the item has none).
    pub strokes: Vec<BowStroke>,
    /// Sounding notes with their string: onset, offset (seconds), string 1–4 (0 unknown).
    pub note_strings: Vec<(f64, f64, u8)>,
}

impl StrokeReferences {
    /// Reads the strokes of corpus item `dir` and takes the strings from its `notes.tsv`
    /// rows (`onset, offset, midi, string, …`).
    pub fn read(dir: &Path, notes: &[Vec<f64>]) -> Result<StrokeReferences> {
        let path = dir.join("strokes.tsv");
        Ok(StrokeReferences {
            strokes: if path.is_file() {
                crate::bowing_data::read_strokes(&path)?
            } else {
                Vec::new()
            },
            note_strings: notes
                .iter()
                .filter(|n| n.len() >= 2)
                .map(|n| (n[0], n[1], n.get(3).map_or(0, |&s| s as u8)))
                .collect(),
        })
    }
}

/// Right answers out of all, pooled over recordings.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Tally {
    /// Answers that are right.
    pub right: usize,
    /// Answers counted.
    pub total: usize,
}

impl Tally {
    /// Adds another recording's tally.
    pub fn add(&mut self, other: &Tally) {
        self.right += other.right;
        self.total += other.total;
    }

    /// Share of right answers (0 when nothing was counted).
    pub fn share(&self) -> f64 {
        if self.total == 0 {
            0.0
        } else {
            self.right as f64 / self.total as f64
        }
    }
}

/// The found stroke sounding at `t_s` (the last one starting at or before it).
fn stroke_at(found: &[BowStroke], t_s: f64) -> Option<&BowStroke> {
    let i = found.partition_point(|s| s.start_s <= t_s);
    i.checked_sub(1).and_then(|i| found.get(i))
}

/// Labelled strokes whose midpoint falls in a found stroke of the same direction.
///
/// ```
/// use performance::{BowDirection::{Down, Up}, BowStroke};
/// use violin_train::evaluate::direction_tally;
/// let s = |a, b, d| BowStroke { start_s: a, end_s: b, direction: d, string: None };
/// let truth = [s(0.0, 1.0, Down), s(1.0, 2.0, Up), s(2.0, 3.0, Down)];
/// let found = [s(0.0, 1.0, Down), s(1.0, 3.0, Up)]; // one change missed
/// let t = direction_tally(&truth, &found);
/// assert_eq!((t.right, t.total), (2, 3));
/// ```
pub fn direction_tally(truth: &[BowStroke], found: &[BowStroke]) -> Tally {
    Tally {
        right: truth
            .iter()
            .filter(|s| {
                stroke_at(found, 0.5 * (s.start_s + s.end_s))
                    .is_some_and(|f| f.direction == s.direction)
            })
            .count(),
        total: truth.len(),
    }
}

/// Frames (30 fps) with a sounding labelled note on a known string (`notes`: onset,
/// offset, string 1–4) where the found stroke sounding then has that string.
pub fn string_tally(notes: &[(f64, f64, u8)], found: &[BowStroke]) -> Tally {
    let mut t = Tally::default();
    for &(onset, offset, string) in notes {
        if !(1..=4).contains(&string)
            || offset.partial_cmp(&onset) != Some(std::cmp::Ordering::Greater)
        {
            continue;
        }
        let first = (onset * 30.0).ceil() as usize;
        let last = (offset * 30.0).ceil() as usize;
        for f in first..last {
            t.total += 1;
            let heard = stroke_at(found, f as f64 / 30.0).and_then(|s| s.string);
            if heard.is_some_and(|h| h.number() == string) {
                t.right += 1;
            }
        }
    }
    t
}
