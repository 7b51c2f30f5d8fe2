//! Portato: how a violinist plays a repeated pitch inside one bow. Without a bow change the
//! string keeps sounding, so a slurred note on the same pitch as the one before would be a
//! tie — inaudible, yet labelled as a new note. Players articulate it instead: the bow slows
//! just before the new note and picks up again (portato, louré), and the sound dips and
//! swells. Both renderers apply this gain to the amplitude around such a note's onset;
//! every other note is untouched.

use performance::TimedNote;

/// Lowest gain, at the repeated note's onset (−10.5 dB).
pub const PORTATO_FLOOR: f64 = 0.3;
/// How long the bow slows before the onset, seconds (at most a quarter of the note before).
pub const PORTATO_FALL_S: f64 = 0.03;
/// How long it takes to pick up again after the onset, seconds.
pub const PORTATO_RISE_S: f64 = 0.03;

/// Whether `notes[i]` repeats the previous note's pitch within the same bow.
pub fn is_portato(notes: &[TimedNote], i: usize) -> bool {
    match (i.checked_sub(1).and_then(|p| notes.get(p)), notes.get(i)) {
        (Some(prev), Some(note)) => !note.bow_change && note.note.midi == prev.note.midi,
        _ => false,
    }
}

/// Amplitude gain (in `PORTATO_FLOOR..=1`) at time `t_s` while `notes[sounding]` sounds:
/// below 1 only in the fall before a portato note's onset and the rise after it.
///
/// ```
/// use corpus::render::portato_gain;
/// use performance::{Note, TimedNote};
/// let note = |onset_s, offset_s, bow_change| TimedNote {
///     note: Note::new(onset_s, offset_s, 69), bow_change, dynamic: 0.5, accent: false,
/// };
/// let notes = [note(0.0, 0.5, true), note(0.5, 1.0, false)]; // A4, A4 under one bow
/// assert_eq!(portato_gain(&notes, 0, 0.2), 1.0);
/// assert!(portato_gain(&notes, 0, 0.49) < 0.5);
/// assert!((portato_gain(&notes, 1, 0.5) - 0.3).abs() < 1e-9);
/// assert_eq!(portato_gain(&notes, 1, 0.6), 1.0);
/// ```
pub fn portato_gain(notes: &[TimedNote], sounding: usize, t_s: f64) -> f64 {
    let Some(note) = notes.get(sounding) else {
        return 1.0;
    };
    let dip = |x: f64| {
        let x = x.clamp(0.0, 1.0);
        let smooth = x * x * (3.0 - 2.0 * x);
        PORTATO_FLOOR + (1.0 - PORTATO_FLOOR) * smooth
    };
    let mut gain = 1.0f64;
    if is_portato(notes, sounding + 1) {
        if let Some(next) = notes.get(sounding + 1) {
            let fall_s = PORTATO_FALL_S.min(0.25 * (next.note.onset_s - note.note.onset_s));
            let before_s = next.note.onset_s - t_s;
            if fall_s > 0.0 && (0.0..fall_s).contains(&before_s) {
                gain = gain.min(dip(before_s / fall_s));
            }
        }
    }
    if is_portato(notes, sounding) {
        let since_s = t_s - note.note.onset_s;
        if (0.0..PORTATO_RISE_S).contains(&since_s) {
            gain = gain.min(dip(since_s / PORTATO_RISE_S));
        }
    }
    gain
}

#[cfg(test)]
mod tests {
    use super::*;
    use performance::Note;

    fn note(onset_s: f64, offset_s: f64, midi: u8, bow_change: bool) -> TimedNote {
        TimedNote {
            note: Note::new(onset_s, offset_s, midi),
            bow_change,
            dynamic: 0.5,
            accent: false,
        }
    }

    #[test]
    fn only_repeated_pitches_under_one_bow_dip() {
        let notes = [
            note(0.0, 0.5, 69, true),
            note(0.5, 1.0, 71, false), // slurred, new pitch
            note(1.0, 1.5, 71, true),  // new bow, same pitch
            note(1.5, 2.0, 71, false), // portato
        ];
        assert!(!is_portato(&notes, 0) && !is_portato(&notes, 1) && !is_portato(&notes, 2));
        assert!(is_portato(&notes, 3) && !is_portato(&notes, 4));
        for t in [0.48, 0.5, 0.52, 0.98, 1.0, 1.02] {
            let i = if t < 0.5 {
                0
            } else if t < 1.0 {
                1
            } else {
                2
            };
            assert_eq!(portato_gain(&notes, i, t), 1.0, "t = {t}");
        }
        // Falls before 1.5, lowest at the onset, back to 1 after the rise.
        let g: Vec<f64> = [1.46, 1.48, 1.499]
            .iter()
            .map(|&t| portato_gain(&notes, 2, t))
            .collect();
        assert!(g[0] > g[1] && g[1] > g[2] && g[2] >= PORTATO_FLOOR, "{g:?}");
        assert!((portato_gain(&notes, 3, 1.5) - PORTATO_FLOOR).abs() < 1e-12);
        assert!(portato_gain(&notes, 3, 1.52) > portato_gain(&notes, 3, 1.51));
        assert_eq!(portato_gain(&notes, 3, 1.5 + PORTATO_RISE_S), 1.0);
        assert_eq!(portato_gain(&notes, 9, 1.5), 1.0);
    }

    #[test]
    fn the_fall_fits_inside_a_short_note() {
        let notes = [note(0.0, 0.06, 69, true), note(0.06, 0.5, 69, false)];
        // A quarter of 60 ms: the first 45 ms keep full level.
        assert_eq!(portato_gain(&notes, 0, 0.044), 1.0);
        assert!(portato_gain(&notes, 0, 0.055) < 1.0);
    }
}
