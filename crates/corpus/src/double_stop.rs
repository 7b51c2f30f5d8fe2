//! Double stops: the second note of a written chord, played on the string next below the
//! melody note's, in the same bow stroke and hand position.
//!
//! The melody (the chord's top note) stays the item's note and pitch label; the second
//! notes are rendered as a voice of their own and mixed under it, and listed in the item's
//! `double_stops.tsv`. A chord whose second note cannot be stopped on the adjacent lower
//! string within a position of the melody's (or is below the G string) is reduced to its
//! top note, as are the third and fourth notes of triple and quadruple chords; the counts go
//! to the manifest.

use fingering::{double_stop_place, Fingering};
use performance::{Note, TimedNote, Timeline};

use crate::score::Score;

/// Level of the second voice relative to the melody: the bow's weight favours the string
/// that carries the tune.
pub const SECOND_VOICE_LEVEL: f32 = 0.8;

/// The double stops of one performed score.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DoubleStops {
    /// The second notes, in time order, each with the fingering that plays it.
    pub notes: Vec<TimedNote>,
    /// Written pitches that were not played: chords reduced to their top note, and the third
    /// and fourth notes of larger chords.
    pub pitches_dropped: usize,
}

impl DoubleStops {
    /// The second voice as a timeline the renderers can play (notes and length only).
    pub fn as_timeline(&self, duration_s: f64) -> Timeline {
        Timeline {
            duration_s,
            notes: self.notes.clone(),
            beats_s: Vec::new(),
            downbeats_s: Vec::new(),
            arousal_2hz: Vec::new(),
            tempo_bpm: 0.0,
        }
    }
}

/// Where a lower note `midi` of a double stop is played under `top`: on the string next
/// below and in reach of the hand (an open string, or within one position of the melody's;
/// [`double_stop_place`]).
///
/// ```
/// use corpus::double_stop::second_place;
/// use fingering::{Fingering, ViolinString};
/// // A5 on the E string in first position over D5 on the A string: a fourth.
/// let top = Fingering::new(ViolinString::E, 1, 4);
/// assert_eq!(second_place(top, 74).map(|f| f.string), Some(ViolinString::A));
/// // Nothing lies below the G string.
/// assert_eq!(second_place(Fingering::new(ViolinString::G, 1, 1), 55), None);
/// ```
pub fn second_place(top: Fingering, midi: u8) -> Option<Fingering> {
    if midi > top.midi() {
        return None;
    }
    double_stop_place(&top, midi)
}

/// The double stops of `score` as performed in `timeline` (one timed note per score note,
/// fingered). Notes without a fingering keep their chords unplayed.
pub fn double_stops(score: &Score, timeline: &Timeline) -> DoubleStops {
    let mut out = DoubleStops::default();
    for (written, played) in score.notes.iter().zip(&timeline.notes) {
        let Some(&second) = written.lower.first() else {
            continue;
        };
        out.pitches_dropped += written.lower.len() - 1;
        let place = played
            .note
            .fingering
            .and_then(|top| second_place(top, second));
        let Some(place) = place else {
            out.pitches_dropped += 1;
            continue;
        };
        out.notes.push(TimedNote {
            note: Note {
                midi: second,
                fingering: Some(place),
                ..played.note
            },
            dynamic: played.dynamic * SECOND_VOICE_LEVEL,
            ..*played
        });
    }
    out
}

/// Adds `second` (rendered second voice) into `melody`, sample by sample.
pub fn mix_into(melody: &mut [f32], second: &[f32]) {
    for (m, s) in melody.iter_mut().zip(second) {
        *m += SECOND_VOICE_LEVEL * s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::score::{Bar, PartNote, Provenance};
    use fingering::ViolinString;
    use performance::TimeSignature;

    fn chord(start_q: f64, midi: u8, lower: Vec<u8>) -> PartNote {
        PartNote {
            start_q,
            dur_q: 1.0,
            midi,
            lower,
            slurred_from_previous: false,
            dynamic: None,
            accent: false,
            staccato: false,
            fermata: false,
        }
    }

    fn played(onset_s: f64, midi: u8, f: Fingering) -> TimedNote {
        TimedNote {
            note: Note {
                fingering: Some(f),
                ..Note::new(onset_s, onset_s + 0.5, midi)
            },
            bow_change: true,
            dynamic: 0.5,
            accent: false,
        }
    }

    #[test]
    fn playable_seconds_are_kept_and_the_rest_counted() {
        let score = Score {
            work: "w".into(),
            id: "w".into(),
            bars: vec![Bar {
                start_q: 0.0,
                len_q: 4.0,
                time_signature: TimeSignature::new(4, 4),
            }],
            notes: vec![
                chord(0.0, 81, vec![74, 62]), // A5 over D5 (and D4 dropped)
                chord(1.0, 60, vec![]),
                chord(2.0, 62, vec![58]), // D4 on the G string: nothing below
                chord(3.0, 76, vec![50]), // below the violin's range
            ],
            tempo_bpm: None,
            provenance: Provenance::default(),
        };
        let timeline = Timeline {
            duration_s: 2.5,
            notes: vec![
                played(0.0, 81, Fingering::new(ViolinString::E, 1, 4)),
                played(0.5, 60, Fingering::new(ViolinString::G, 1, 3)),
                played(1.0, 62, Fingering::new(ViolinString::G, 1, 4)),
                played(1.5, 76, Fingering::open(ViolinString::E, 1)),
            ],
            beats_s: vec![],
            downbeats_s: vec![],
            arousal_2hz: vec![],
            tempo_bpm: 120.0,
        };
        let ds = double_stops(&score, &timeline);
        assert_eq!(ds.notes.len(), 1);
        let n = &ds.notes[0];
        assert_eq!(n.note.midi, 74);
        assert_eq!(n.note.onset_s, 0.0);
        assert_eq!(n.note.fingering.map(|f| f.string), Some(ViolinString::A));
        assert!((n.dynamic - 0.5 * SECOND_VOICE_LEVEL).abs() < 1e-6);
        assert_eq!(ds.pitches_dropped, 3);
        let voice = ds.as_timeline(2.5);
        assert_eq!(voice.notes.len(), 1);
        assert_eq!(voice.duration_s, 2.5);
    }

    #[test]
    fn far_positions_are_not_a_double_stop() {
        // E6 high on the E string (7th position) over D4 on the A string: out of reach.
        let top = Fingering::new(ViolinString::E, 7, 1);
        assert_eq!(second_place(top, 62), None);
        // The open A string under any E-string note is fine.
        assert!(second_place(top, 69).is_some_and(|f| f.is_open()));
    }

    #[test]
    fn mixing_adds_the_second_voice_at_its_level() {
        let mut m = vec![0.5f32, 0.0, 0.25];
        mix_into(&mut m, &[1.0, 1.0]);
        assert_eq!(m, vec![0.5 + SECOND_VOICE_LEVEL, SECOND_VOICE_LEVEL, 0.25]);
    }
}
