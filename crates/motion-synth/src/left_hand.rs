//! Left hand and string (SPEC §6): from each note's fingering, the hand's place along the
//! neck and the bowed string per frame, with short glides before each note.
//!
//! A value changes only when a note asks for a different one, and then glides (smoothstep:
//! zero speed at both ends) during the `glide_s` before the note's onset — or during the
//! second half of the previous note if that is shorter — so the hand has arrived when the
//! note starts. Before the first note the first note's values are held, after the last
//! note the last ones.
//!
//! While a double stop's other note ([`performance::Performance::double_stops`]) sounds
//! with the line's note, the bow lies across both strings (the mean of their indices); the
//! hand stays where the line's note has it.

use fingering::{partner_place, Fingering, FingeringPlanner, OptimalPlanner};

use crate::error::Result;
use crate::geometry::smoothstep;
use performance::{Note, CHORD_S};

/// Glide lengths of the left hand and of string crossings.
#[derive(Debug, Clone, PartialEq)]
pub struct LeftHandConfig {
    /// Length of a shift of position, seconds (0.1).
    pub shift_s: f64,
    /// Length of a string crossing, seconds (0.06).
    pub string_crossing_s: f64,
}

impl Default for LeftHandConfig {
    fn default() -> Self {
        LeftHandConfig {
            shift_s: 0.1,
            string_crossing_s: 0.06,
        }
    }
}

impl LeftHandConfig {
    pub(crate) fn is_valid(&self) -> bool {
        [self.shift_s, self.string_crossing_s]
            .iter()
            .all(|v| v.is_finite() && *v >= 0.0)
    }
}

/// Lowest and highest pitch the fallback planner is given (G3 … A7): pitches outside the
/// violin's range are played at the nearest end of it.
const PLAYABLE_MIDI: (u8, u8) = (55, 105);

/// The fingering of every note: the given one, or for notes without one the choice of
/// [`OptimalPlanner`] over the whole melody (pitches outside G3..A7 clamped into range).
pub fn resolve_fingerings(notes: &[Note]) -> Result<Vec<Fingering>> {
    let mut out: Vec<Fingering> = Vec::with_capacity(notes.len());
    if notes.iter().all(|n| n.fingering.is_some()) {
        out.extend(notes.iter().filter_map(|n| n.fingering));
        return Ok(out);
    }
    let midi: Vec<u8> = notes
        .iter()
        .map(|n| n.midi.clamp(PLAYABLE_MIDI.0, PLAYABLE_MIDI.1))
        .collect();
    let plan = OptimalPlanner::default().plan(&midi)?;
    out.extend(
        notes
            .iter()
            .zip(plan)
            .map(|(n, f)| n.fingering.unwrap_or(f)),
    );
    Ok(out)
}

/// Fills `out[f]` (frame `f` at `fps`) from `events` — `(onset_s, value)` in onset order —
/// with glides of `glide_s` ending at each onset where the value changes.
pub fn glide_track(events: &[(f64, f64)], glide_s: f64, fps: f64, out: &mut [f64]) {
    let Some(&(_, first)) = events.first() else {
        out.fill(0.0);
        return;
    };
    // Walk frames and events together; `current` is the value reached so far.
    let mut current = first;
    let mut next = 1usize;
    let mut prev_onset = events[0].0;
    for (f, slot) in out.iter_mut().enumerate() {
        let t = f as f64 / fps;
        // Settle every event whose onset has passed.
        while next < events.len() && events[next].0 <= t {
            current = events[next].1;
            prev_onset = events[next].0;
            next += 1;
        }
        *slot = current;
        if let Some(&(onset, target)) = events.get(next) {
            if target != current {
                let start = (onset - glide_s).max(prev_onset + 0.5 * (onset - prev_onset));
                if t > start && onset > start {
                    *slot =
                        current + (target - current) * smoothstep((t - start) / (onset - start));
                }
            }
        }
    }
}

/// The line note (index into `notes`, sorted by onset) a double-stop note `d` is played
/// with: the last one starting by `d`'s onset, if they sound together.
fn line_note_of(notes: &[Note], d: &Note) -> Option<usize> {
    let l = notes
        .partition_point(|n| n.onset_s <= d.onset_s + CHORD_S)
        .checked_sub(1)?;
    notes.get(l).filter(|n| n.sounds_with(d)).map(|_| l)
}

/// The second voice with the place of each note: its own fingering, else the neighbouring
/// string of its line note's place ([`partner_place`]); `None` when neither is known.
pub fn second_voice(
    notes: &[Note],
    fingerings: &[Fingering],
    double_stops: &[Note],
) -> Vec<(Note, Option<Fingering>)> {
    double_stops
        .iter()
        .map(|d| {
            let place = d.fingering.or_else(|| {
                line_note_of(notes, d)
                    .and_then(|l| fingerings.get(l))
                    .and_then(|f| partner_place(f, d.midi))
            });
            (*d, place)
        })
        .collect()
}

/// The bowed string's events (time, string index 0 = G … 3 = E) in time order: each line
/// note's `line_string`, and while a note of the second voice ([`second_voice`]) sounds
/// with its line note, the mean of the two strings, so the bow lies across both (a second
/// note without a place counts as on the line's string).
pub(crate) fn bowed_string_events(
    notes: &[Note],
    second: &[(Note, Option<Fingering>)],
    line_string: impl Fn(usize) -> f64,
) -> Vec<(f64, f64)> {
    let mut events: Vec<(f64, f64)> = Vec::with_capacity(notes.len() + 2 * second.len());
    events.extend(
        notes
            .iter()
            .enumerate()
            .map(|(i, n)| (n.onset_s, line_string(i))),
    );
    for (d, place) in second {
        let Some(l) = line_note_of(notes, d) else {
            continue;
        };
        let (line, on_line) = (&notes[l], line_string(l));
        let string = place.map_or(on_line, |f| f64::from(f.string.number() - 1));
        events.push((d.onset_s.max(line.onset_s), 0.5 * (on_line + string)));
        let together_until = d.offset_s.min(line.offset_s);
        if line.offset_s > together_until + CHORD_S {
            events.push((together_until, on_line));
        }
    }
    // Stable: at equal times a double stop's event follows (and overrides) the line's.
    events.sort_by(|a, b| a.0.total_cmp(&b.0));
    events
}

/// Per-frame string index (0 = G … 3 = E) and hand place (semitones from the nut); while a
/// note of the second voice (`second`, from [`second_voice`]) sounds with its line note,
/// the string index lies between the two notes' strings.
pub fn left_hand_tracks(
    notes: &[Note],
    fingerings: &[Fingering],
    second: &[(Note, Option<Fingering>)],
    fps: f64,
    cfg: &LeftHandConfig,
    string_index: &mut [f64],
    hand_semitones: &mut [f64],
) {
    let string_of = |i: usize| {
        fingerings
            .get(i)
            .map_or(0.0, |f| f64::from(f.string.number() - 1))
    };
    let strings = bowed_string_events(notes, second, string_of);
    // An open string keeps the hand where it was (its position is the planner's context).
    let hands: Vec<(f64, f64)> = notes
        .iter()
        .zip(fingerings)
        .map(|(n, f)| (n.onset_s, f64::from(f.hand_offset_semitones())))
        .collect();
    glide_track(&strings, cfg.string_crossing_s, fps, string_index);
    glide_track(&hands, cfg.shift_s, fps, hand_semitones);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_double_stop_bows_across_both_strings() {
        use fingering::ViolinString::{A, D, E};
        // D5 (A string); E5 (A string, 3rd position) with G4 under it; B5 (E string)
        // joined by E5 on the A string for 0.3 s.
        let notes = [
            Note::new(0.0, 1.0, 74),
            Note::new(1.0, 2.0, 76),
            Note::new(2.0, 3.0, 83),
        ];
        let fingerings = [
            Fingering::new(A, 1, 3),
            Fingering::new(A, 3, 2),
            Fingering::new(E, 3, 3),
        ];
        let second = [
            Note {
                fingering: Some(Fingering::new(D, 3, 1)),
                ..Note::new(1.0, 2.0, 67)
            },
            Note::new(2.3, 2.6, 76), // no fingering: the A string next to B5's E
        ];
        let second = second_voice(&notes, &fingerings, &second);
        let places: Vec<Option<Fingering>> = second.iter().map(|(_, f)| *f).collect();
        assert_eq!(
            places,
            vec![
                Some(Fingering::new(D, 3, 1)),
                partner_place(&fingerings[2], 76)
            ]
        );
        assert_eq!(places[1].map(|f| f.string), Some(A));
        let string_of = |i: usize| f64::from(fingerings[i].string.number() - 1);
        let events = bowed_string_events(&notes, &second, string_of);
        // 2 (A), 1.5 across D and A, 3 (E), 2.5 across A and E, back to 3.
        assert_eq!(
            events,
            vec![
                (0.0, 2.0),
                (1.0, 2.0),
                (1.0, 1.5),
                (2.0, 3.0),
                (2.3, 2.5),
                (2.6, 3.0)
            ]
        );
        let (mut track, mut hand) = (vec![0.0; 90], vec![0.0; 90]);
        let cfg = LeftHandConfig::default();
        left_hand_tracks(
            &notes,
            &fingerings,
            &second,
            30.0,
            &cfg,
            &mut track,
            &mut hand,
        );
        assert_eq!(track[45], 1.5);
        assert_eq!(track[75], 2.5);
        assert_eq!(track[85], 3.0);
        assert_eq!(hand[45], f64::from(fingerings[1].hand_offset_semitones()));
        // No second voice: the line's strings only.
        let alone = bowed_string_events(&notes, &[], string_of);
        assert_eq!(alone, vec![(0.0, 2.0), (1.0, 2.0), (2.0, 3.0)]);
    }

    #[test]
    fn glides_end_at_the_onset_and_hold_otherwise() {
        let mut out = vec![0.0; 60];
        glide_track(&[(0.2, 1.0), (1.0, 3.0)], 0.1, 30.0, &mut out);
        assert_eq!(out[0], 1.0); // held before the first note
        assert_eq!(out[26], 1.0); // before the glide (starts at 0.9 s = frame 27)
        assert!(out[28] > 1.0 && out[28] < 3.0);
        assert_eq!(out[30], 3.0); // arrived on the onset
        assert_eq!(out[59], 3.0);
    }

    #[test]
    fn close_notes_glide_in_the_second_half_of_the_previous_note() {
        let mut out = vec![0.0; 12];
        glide_track(&[(0.0, 0.0), (0.1, 2.0), (0.2, 0.0)], 0.1, 30.0, &mut out);
        assert_eq!(out[3], 2.0);
        assert_eq!(out[6], 0.0);
        assert!(out.windows(2).all(|w| (w[1] - w[0]).abs() <= 2.0));
    }

    #[test]
    fn missing_fingerings_are_planned_and_given_ones_kept() {
        use fingering::ViolinString;
        let given = Fingering::new(ViolinString::D, 3, 1);
        let notes = vec![
            Note::new(0.0, 0.5, 40), // below the violin: clamped to G3
            Note {
                fingering: Some(given),
                ..Note::new(0.5, 1.0, 67)
            },
        ];
        let f = resolve_fingerings(&notes).unwrap();
        assert_eq!(f[0].string, ViolinString::G);
        assert_eq!(f[1], given);
    }
}
