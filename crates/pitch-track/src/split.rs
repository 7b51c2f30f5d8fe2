//! Splitting notes at times another detector found (e.g. bow changes): on a bowed string
//! every bow change starts a new note, even when the pitch stays the same and the attack is
//! too soft for the pitch path or the onset novelty to show.

use crate::notes::Note;

/// Splits every note that contains one of `times_s` at least `min_part_s` away from both of
/// its ends into two notes of the same pitch, the second starting at that time. `times_s`
/// must be sorted; times outside every note (rests) are ignored.
///
/// ```
/// use pitch_track::{split_notes_at, Note};
/// let notes = vec![Note { onset_s: 1.0, offset_s: 2.0, midi: 69 }];
/// let split = split_notes_at(&notes, &[1.02, 1.5, 3.0], 0.08);
/// assert_eq!(split.len(), 2); // 1.02 is too close to the onset; 3.0 is in a rest
/// assert_eq!((split[0].offset_s, split[1].onset_s, split[1].midi), (1.5, 1.5, 69));
/// ```
pub fn split_notes_at(notes: &[Note], times_s: &[f64], min_part_s: f64) -> Vec<Note> {
    let mut out = Vec::with_capacity(notes.len() + times_s.len());
    let mut next = 0usize;
    for note in notes {
        while next < times_s.len() && times_s[next] < note.onset_s + min_part_s {
            next += 1;
        }
        let mut start = note.onset_s;
        while next < times_s.len() && times_s[next] <= note.offset_s - min_part_s {
            let t = times_s[next];
            if t >= start + min_part_s {
                out.push(Note {
                    onset_s: start,
                    offset_s: t,
                    midi: note.midi,
                });
                start = t;
            }
            next += 1;
        }
        out.push(Note {
            onset_s: start,
            offset_s: note.offset_s,
            midi: note.midi,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn note(on: f64, off: f64, midi: u8) -> Note {
        Note {
            onset_s: on,
            offset_s: off,
            midi,
        }
    }

    #[test]
    fn splits_inside_notes_only_and_keeps_the_covered_time() {
        let notes = [note(0.0, 1.0, 60), note(1.0, 1.1, 62), note(2.0, 3.0, 64)];
        let times = [0.5, 0.55, 0.7, 1.05, 1.5, 2.95, 5.0];
        let out = split_notes_at(&notes, &times, 0.08);
        let spans: Vec<(f64, f64, u8)> = out
            .iter()
            .map(|n| (n.onset_s, n.offset_s, n.midi))
            .collect();
        // 0.55 is too close to the split at 0.5; 1.05 inside a 0.1 s note; 1.5 in a rest;
        // 2.95 too close to the offset; 5.0 after the last note.
        assert_eq!(
            spans,
            vec![
                (0.0, 0.5, 60),
                (0.5, 0.7, 60),
                (0.7, 1.0, 60),
                (1.0, 1.1, 62),
                (2.0, 3.0, 64)
            ]
        );
    }

    #[test]
    fn no_times_or_no_notes_change_nothing() {
        let notes = [note(0.0, 1.0, 60)];
        assert_eq!(split_notes_at(&notes, &[], 0.08), notes.to_vec());
        assert!(split_notes_at(&[], &[0.5], 0.08).is_empty());
    }
}
