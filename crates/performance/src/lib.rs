//! # performance
//!
//! The vocabulary of violin-skeleton (layer 1): the types every stage speaks, so that
//! analysis, the synthetic corpus, MIDI input and motion synthesis share one language —
//! *audio → analysis → a [`Performance`] → motion* (ARCHITECTURE.md).
//!
//! * [`Note`] — the one note type: onset, offset, MIDI pitch and (when known) its
//!   [`fingering::Fingering`];
//! * [`ArousalCurve`] — arousal over time (DEAM convention) and [`arousal_proxy_of_spans`];
//! * [`Performance`] — what is played when, and how: notes, bow changes, beats, downbeats,
//!   arousal, dynamics; always valid;
//! * [`Analysis`] / [`F0Track`] — what a recording tells, in the `analysis.json` schema;
//! * [`Timeline`] / [`TimedNote`] — a played piece with articulation and labels (the corpus
//!   and MIDI input), → [`Timeline::to_performance`];
//! * [`Meter`] — beats per bar and how a beat divides;
//! * [`match_events`] / [`event_prf`] — the one event matcher (mir_eval's conventions) for
//!   onsets, beats, downbeats and bow changes;
//! * [`midi`] (feature `midi`) — Standard MIDI Files → [`midi::MidiScore`] (every note,
//!   beats, bars) and [`Timeline`];
//! * [`bow_directions`] — down- and up-bows from bow changes, notes and bars.
//! * [`heard_bow_directions`] — the same from bow changes and bars found in audio.
//! * [`hooks_for_downbeats`] — the bow changes a player drops so that bars start down-bow.
//!
//! ```
//! use performance::{ArousalCurve, Performance};
//! let perf = Performance::builder(2.0)
//!     .note(0.0, 1.0, 67)
//!     .note(1.0, 2.0, 71)
//!     .bow_changes(vec![1.0])
//!     .beats(vec![0.0, 0.5, 1.0, 1.5])
//!     .arousal(ArousalCurve::deam(vec![0.0, 0.2, 0.4, 0.6]))
//!     .build()?;
//! assert_eq!(perf.notes()[1].midi, 71);
//! let f = performance::event_prf(perf.beats_s(), &[0.01, 0.52, 1.2], 0.07);
//! assert_eq!(f.recall, 0.5);
//! # Ok::<(), performance::PerformanceError>(())
//! ```

mod analysis;
mod arousal;
mod bowing;
mod error;
mod matching;
mod meter;
#[cfg(feature = "midi")]
pub mod midi;
#[cfg(feature = "midi")]
mod midi_line;
#[cfg(feature = "midi")]
mod midi_score;
mod note;
mod performance;
mod stroke;
mod timeline;
mod validate;

pub use crate::performance::{
    Performance, PerformanceBuilder, PerformanceParts, MAX_PERFORMANCE_S,
};
pub use analysis::{tempo_per_beat, Analysis, F0Track, ANALYSIS_SCHEMA_VERSION};
pub use arousal::{arousal_proxy_of_spans, ArousalCurve};
pub use bowing::{
    bow_directions, heard_bow_directions, hooks_for_downbeats, BowDirection, HEARD_ON_BEAT_S,
    MAX_HOOKED_STROKE_S, RETAKE_REST_S,
};
#[cfg(feature = "midi")]
pub use error::MidiError;
pub use error::{PerformanceError, PerformanceFileError};
pub use matching::{event_prf, f_measure, match_events, Prf};
pub use meter::{Meter, TimeSignature};
pub use note::{double_stop_partners, Note, CHORD_S, DOUBLE_STOP_OVERLAP_S};
pub use stroke::{strokes_of, BowStroke};
pub use timeline::{arousal_proxy, TimedNote, Timeline};

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
