//! [`Note`]: the one note type of the workspace — when it sounds, its pitch and, when known,
//! where it is played. Its JSON form puts the fingering fields beside the times, strictly
//! all-or-none (serde's `flatten` on an `Option` would silently drop a malformed fingering).

use fingering::{Fingering, Placement, ViolinString};
use serde::{Deserialize, Serialize};

use crate::error::PerformanceError;

/// One note: onset and offset in seconds, MIDI pitch and (when known) its fingering. In JSON
/// the fingering's fields sit beside the times, as in `analysis.json`:
/// `{"onset_s", "offset_s", "midi", "string", "position", "finger"}` (the three fingering
/// fields all present, or all absent; `"placement": "low" | "high"` when the finger is not in
/// its normal place).
///
/// ```
/// let n = performance::Note::new(0.5, 1.0, 67);
/// assert_eq!(serde_json::to_string(&n)?, r#"{"onset_s":0.5,"offset_s":1.0,"midi":67}"#);
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "NoteRecord", into = "NoteRecord")]
pub struct Note {
    /// Start, seconds.
    pub onset_s: f64,
    /// End, seconds (after the onset).
    pub offset_s: f64,
    /// MIDI pitch (60 = C4).
    pub midi: u8,
    /// Where the note is played, when known (see [`crate::Performance::with_fingering`]).
    pub fingering: Option<Fingering>,
    /// MIDI velocity (1..=127) when the note comes from a MIDI file; `None` for notes
    /// found in audio. JSON `"velocity"`, left out when `None`.
    pub velocity: Option<u8>,
}

/// Notes whose onsets are closer than this (seconds) start together: a chord.
pub const CHORD_S: f64 = 0.03;
/// A note that starts while another sounds is a double stop with it when they overlap by
/// at least this long (seconds) and by half the shorter note ([`Note::sounds_with`]).
pub const DOUBLE_STOP_OVERLAP_S: f64 = 0.1;

impl Note {
    /// A note without fingering.
    pub fn new(onset_s: f64, offset_s: f64, midi: u8) -> Note {
        Note {
            onset_s,
            offset_s,
            midi,
            fingering: None,
            velocity: None,
        }
    }

    /// Length in seconds.
    pub fn duration_s(&self) -> f64 {
        self.offset_s - self.onset_s
    }

    /// Whether `other` is played together with this note, as a double stop or chord: the
    /// two sound at once, and `other` starts within [`CHORD_S`] of it or they overlap by at
    /// least [`DOUBLE_STOP_OVERLAP_S`] and by half the shorter note (a legato overlap of a
    /// few milliseconds is not a double stop, nor is a note that follows a 20 ms one).
    ///
    /// ```
    /// use performance::Note;
    /// let a4 = Note::new(0.0, 1.0, 69);
    /// assert!(a4.sounds_with(&Note::new(0.01, 1.0, 62))); // a chord
    /// assert!(a4.sounds_with(&Note::new(0.5, 1.5, 74))); // held under the next note
    /// assert!(!a4.sounds_with(&Note::new(0.98, 2.0, 71))); // legato
    /// let blip = Note::new(0.0, 0.02, 69);
    /// assert!(!blip.sounds_with(&Note::new(0.02, 1.0, 71))); // one after the other
    /// ```
    pub fn sounds_with(&self, other: &Note) -> bool {
        let overlap = self.offset_s.min(other.offset_s) - self.onset_s.max(other.onset_s);
        if overlap <= 0.0 {
            return false;
        }
        let shorter = self.duration_s().min(other.duration_s());
        (other.onset_s - self.onset_s).abs() < CHORD_S
            || (overlap >= DOUBLE_STOP_OVERLAP_S && overlap >= 0.5 * shorter)
    }
}

/// For each note of `notes` (sorted by onset), the index of the melodic line's note it is
/// played together with ([`Note::sounds_with`]: a double stop or chord), or `None` for a
/// note of the line. Notes `in_line` refuses (for instance pitches no string plays) are
/// neither: `None`, and never a partner.
///
/// ```
/// use performance::{double_stop_partners, Note};
/// let notes = [
///     Note::new(0.0, 1.0, 76), // E5 …
///     Note::new(0.0, 1.0, 67), // … over G4: a double stop
///     Note::new(1.0, 2.0, 74),
/// ];
/// assert_eq!(double_stop_partners(&notes, |_| true), vec![None, Some(0), None]);
/// ```
pub fn double_stop_partners(notes: &[Note], in_line: impl Fn(&Note) -> bool) -> Vec<Option<usize>> {
    let mut line: Option<usize> = None;
    notes
        .iter()
        .enumerate()
        .map(|(i, n)| {
            if !in_line(n) {
                return None;
            }
            match line {
                Some(l) if notes[l].sounds_with(n) => Some(l),
                _ => {
                    line = Some(i);
                    None
                }
            }
        })
        .collect()
}

/// A note as it appears in `analysis.json` and performance files.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub(crate) struct NoteRecord {
    onset_s: f64,
    offset_s: f64,
    midi: u8,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    string: Option<ViolinString>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    position: Option<u8>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    finger: Option<u8>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    placement: Option<Placement>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    velocity: Option<u8>,
}

impl TryFrom<NoteRecord> for Note {
    type Error = PerformanceError;
    fn try_from(r: NoteRecord) -> Result<Note, PerformanceError> {
        let fingering = match (r.string, r.position, r.finger) {
            (Some(string), Some(position), Some(finger)) => Some(Fingering::with_placement(
                string,
                position,
                finger,
                r.placement.unwrap_or_default(),
            )),
            (None, None, None) if r.placement.is_none() => None,
            // serde reports where in the file the note is.
            _ => return Err(PerformanceError::PartialFingering),
        };
        Ok(Note {
            onset_s: r.onset_s,
            offset_s: r.offset_s,
            midi: r.midi,
            fingering,
            velocity: r.velocity,
        })
    }
}

impl From<Note> for NoteRecord {
    fn from(n: Note) -> NoteRecord {
        let f = n.fingering;
        NoteRecord {
            onset_s: n.onset_s,
            offset_s: n.offset_s,
            midi: n.midi,
            string: f.map(|f| f.string),
            position: f.map(|f| f.position),
            finger: f.map(|f| f.finger),
            placement: f.map(|f| f.placement).filter(|p| !p.is_normal()),
            velocity: n.velocity,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fingering_fields_sit_beside_the_times() {
        let n = Note {
            fingering: Some(Fingering::new(ViolinString::D, 1, 3)),
            ..Note::new(0.5, 1.0, 67)
        };
        let text = serde_json::to_string(&n).unwrap();
        assert_eq!(
            text,
            r#"{"onset_s":0.5,"offset_s":1.0,"midi":67,"string":2,"position":1,"finger":3}"#
        );
        assert_eq!(serde_json::from_str::<Note>(&text).unwrap(), n);
        let bare: Note = serde_json::from_str(r#"{"onset_s":0,"offset_s":1,"midi":60}"#).unwrap();
        assert_eq!(bare.fingering, None);
    }

    #[test]
    fn partial_or_bad_fingering_is_an_error() {
        let partial = r#"{"onset_s":0,"offset_s":1,"midi":60,"string":2}"#;
        let e = serde_json::from_str::<Note>(partial).unwrap_err();
        assert!(e.to_string().contains("part of its fingering"), "{e}");
        let bad_string =
            r#"{"onset_s":0,"offset_s":1,"midi":60,"string":7,"position":1,"finger":1}"#;
        assert!(serde_json::from_str::<Note>(bad_string).is_err());
    }
}
