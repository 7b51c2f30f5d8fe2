//! The strokes of an analysis: one per bow change, with its direction (the bowing rules for
//! heard strokes, [`performance::heard_bow_directions`]: alternation, a pickup up-bow, a
//! retake to down-bow after a rest, a down-bow on every downbeat; decoded together with
//! the stroke network's down-bow output and the bars when its weights carry a direction
//! decoder: `StrokeAnalysis::directions`) and the string the stroke network heard (the
//! string of the stroke's first note by the fingering when the model gives no strings, as
//! the CNN does).

use bowing_net::stroke::StrokeAnalysis;
use performance::{strokes_of, BowDirection, BowStroke, Note};

/// Strokes over `notes` from the bow changes and their directions, with the network's
/// strings where `bowed` has them.
pub(crate) fn strokes_with_strings(
    bowed: &StrokeAnalysis,
    bow_changes_s: &[f64],
    directions: &[BowDirection],
    notes: &[Note],
) -> Vec<BowStroke> {
    let mut strokes = strokes_of(bow_changes_s, directions, notes);
    bowed.assign_strings(&mut strokes);
    strokes
}

/// Replaces the direction of each change that starts one of the chunks' own strokes
/// (`heard`, moved to file time) by that stroke's direction.
pub(crate) fn keep_heard_directions(
    bow_changes_s: &[f64],
    directions: &mut [BowDirection],
    heard: &[BowStroke],
) {
    for (c, d) in bow_changes_s.iter().zip(directions.iter_mut()) {
        if let Some(h) = heard.iter().find(|h| (h.start_s - c).abs() < 1e-6) {
            *d = h.direction;
        }
    }
}

/// Strokes over a whole file from its changes and directions, with the strings of the
/// chunks' strokes that start at the same time (`heard`, the chunks' own strokes moved to
/// file time).
pub(crate) fn strokes_with_heard_strings(
    bow_changes_s: &[f64],
    directions: &[BowDirection],
    notes: &[Note],
    heard: &[BowStroke],
) -> Vec<BowStroke> {
    let mut strokes = strokes_of(bow_changes_s, directions, notes);
    for s in &mut strokes {
        if let Some(h) = heard.iter().find(|h| (h.start_s - s.start_s).abs() < 1e-6) {
            s.string = h.string.or(s.string);
        }
    }
    strokes
}

#[cfg(test)]
mod tests {
    use super::*;
    use bowing_net::stroke::FrameOutputs;
    use fingering::ViolinString;

    #[test]
    fn strings_come_from_the_network_when_it_has_them() {
        let notes = [Note::new(0.0, 1.0, 67), Note::new(1.0, 2.0, 69)];
        let dirs = [BowDirection::Down, BowDirection::Up];
        let mut bowed = StrokeAnalysis {
            bow_changes_s: vec![0.0, 1.0],
            played_s: vec![(0.0, 2.0)],
            frames: FrameOutputs {
                change: vec![0.0; 60],
                string: vec![[0.0, 0.0, 0.9, 0.1]; 60],
                down: Vec::new(),
            },
            direction_decoder: None,
        };
        let s = strokes_with_strings(&bowed, &[0.0, 1.0], &dirs, &notes);
        assert_eq!(s.len(), 2);
        assert!(s.iter().all(|s| s.string == Some(ViolinString::A)));
        assert_eq!(s[1].direction, BowDirection::Up);
        bowed.frames.string.clear();
        let s = strokes_with_strings(&bowed, &[0.0, 1.0], &dirs, &notes);
        assert!(
            s.iter().all(|s| s.string.is_none()),
            "no fingering, no network strings"
        );
        let heard = [BowStroke {
            start_s: 1.0,
            end_s: 2.0,
            direction: BowDirection::Up,
            string: Some(ViolinString::E),
        }];
        let s = strokes_with_heard_strings(&[0.0, 1.0], &dirs, &notes, &heard);
        assert_eq!((s[0].string, s[1].string), (None, Some(ViolinString::E)));
    }
}
