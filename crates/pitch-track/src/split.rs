//! Splitting notes at times another detector found (e.g. bow changes): on a bowed string
//! every bow change starts a new note, even when the pitch stays the same and the attack is
//! too soft for the pitch path or the onset novelty to show.

use performance::Note;

/// Splits every note that contains one of `times_s` at least `min_part_s` away from both of
/// its ends into two notes of the same pitch, the second starting at that time. `times_s`
/// must be sorted; times outside every note (rests) are ignored.
///
/// ```
/// use pitch_track::{split_notes_at, Note};
/// let notes = vec![Note::new(1.0, 2.0, 69)];
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
                    ..*note
                });
                start = t;
            }
            next += 1;
        }
        out.push(Note {
            onset_s: start,
            ..*note
        });
    }
    out
}

/// Moves each note's onset back to the latest of `times_s` that lies less than
/// `max_lead_s` before it (and after the previous note's onset), shortening the previous
/// note if it overlaps: the pitch path confirms a new note only after a few frames of its
/// pitch, while a bow change marks when it began. `times_s` must be sorted.
///
/// ```
/// use pitch_track::{start_notes_at, Note};
/// let notes = [
///     Note::new(0.0, 1.02, 69),
///     Note::new(1.02, 2.0, 71),
/// ];
/// let moved = start_notes_at(&notes, &[1.0, 1.5], 0.03);
/// assert_eq!((moved[0].offset_s, moved[1].onset_s), (1.0, 1.0));
/// assert_eq!(moved[1].offset_s, 2.0);
/// ```
pub fn start_notes_at(notes: &[Note], times_s: &[f64], max_lead_s: f64) -> Vec<Note> {
    let mut out: Vec<Note> = Vec::with_capacity(notes.len());
    for note in notes {
        let mut n = *note;
        let j = times_s.partition_point(|&t| t < n.onset_s);
        if let Some(&t) = j.checked_sub(1).and_then(|k| times_s.get(k)) {
            let after_previous = out.last().is_none_or(|p| t > p.onset_s);
            if n.onset_s - t < max_lead_s && after_previous {
                n.onset_s = t;
                if let Some(p) = out.last_mut() {
                    p.offset_s = p.offset_s.min(t);
                }
            }
        }
        out.push(n);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn note(on: f64, off: f64, midi: u8) -> Note {
        Note::new(on, off, midi)
    }

    #[test]
    fn onsets_move_back_to_a_time_just_before_them_only() {
        let notes = [note(0.0, 0.5, 60), note(0.5, 1.0, 62), note(1.2, 2.0, 64)];
        // 0.48 leads the second note by 20 ms; 1.1 leads the third by 100 ms (too far);
        // nothing precedes the first.
        let out = start_notes_at(&notes, &[0.48, 1.1], 0.03);
        let spans: Vec<(f64, f64)> = out.iter().map(|n| (n.onset_s, n.offset_s)).collect();
        assert_eq!(spans, vec![(0.0, 0.48), (0.48, 1.0), (1.2, 2.0)]);
        // A time at or before the previous onset never reorders notes.
        let tight = [note(0.0, 0.01, 60), note(0.01, 0.5, 62)];
        let out = start_notes_at(&tight, &[0.0], 0.03);
        assert_eq!(out[1].onset_s, 0.01);
        assert!(start_notes_at(&[], &[1.0], 0.03).is_empty());
        assert_eq!(start_notes_at(&notes, &[], 0.03), notes.to_vec());
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
