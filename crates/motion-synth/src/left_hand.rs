//! Left hand and string (SPEC §6): from each note's fingering, the hand's place along the
//! neck and the bowed string per frame, with short glides before each note.
//!
//! A value changes only when a note asks for a different one, and then glides (smoothstep:
//! zero speed at both ends) during the `glide_s` before the note's onset — or during the
//! second half of the previous note if that is shorter — so the hand has arrived when the
//! note starts. Before the first note the first note's values are held, after the last
//! note the last ones.

use fingering::{Fingering, FingeringPlanner, OptimalPlanner};

use crate::error::Result;
use crate::geometry::smoothstep;
use crate::performance::PlayedNote;

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
pub fn resolve_fingerings(notes: &[PlayedNote]) -> Result<Vec<Fingering>> {
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

/// Per-frame string index (0 = G … 3 = E) and hand place (semitones from the nut).
pub fn left_hand_tracks(
    notes: &[PlayedNote],
    fingerings: &[Fingering],
    fps: f64,
    cfg: &LeftHandConfig,
    string_index: &mut [f64],
    hand_semitones: &mut [f64],
) {
    let strings: Vec<(f64, f64)> = notes
        .iter()
        .zip(fingerings)
        .map(|(n, f)| (n.onset_s, f64::from(f.string.number() - 1)))
        .collect();
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
            PlayedNote::new(0.0, 0.5, 40), // below the violin: clamped to G3
            PlayedNote {
                fingering: Some(given),
                ..PlayedNote::new(0.5, 1.0, 67)
            },
        ];
        let f = resolve_fingerings(&notes).unwrap();
        assert_eq!(f[0].string, ViolinString::G);
        assert_eq!(f[1], given);
    }
}
