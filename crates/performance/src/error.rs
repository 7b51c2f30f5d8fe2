//! Errors of the vocabulary crate: what is wrong with a performance, a file or a MIDI file.

use std::path::PathBuf;

/// What is wrong with a [`crate::Performance`]: every check of [`crate::Performance::new`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PerformanceError {
    /// The duration is zero, negative, not finite or over a day.
    #[error("duration {duration_s} s is not a positive number of seconds up to a day (86 400 s)")]
    InvalidDuration {
        /// The duration given.
        duration_s: f64,
    },
    /// The performance has no notes: there is nothing to animate.
    #[error("the performance has no notes; give at least one note to animate")]
    Empty,
    /// A time or level is NaN or infinite.
    #[error("{field}[{index}] is {value}, not a finite number")]
    NonFinite {
        /// The field (`"notes.onset_s"`, `"beats_s"`, …).
        field: &'static str,
        /// Index in the field's list.
        index: usize,
        /// The value.
        value: f64,
    },
    /// A list of times is not strictly increasing.
    #[error("{field}[{index}] = {value} s is not after the previous entry; sort the list and drop duplicates")]
    Unsorted {
        /// The field.
        field: &'static str,
        /// Index of the first entry out of order.
        index: usize,
        /// Its time.
        value: f64,
    },
    /// A time lies outside `[0, duration_s]`.
    #[error("{field}[{index}] = {value} s lies outside the performance [0, {duration_s}] s")]
    OutOfRange {
        /// The field.
        field: &'static str,
        /// Index in the field's list.
        index: usize,
        /// The time.
        value: f64,
        /// The performance's duration.
        duration_s: f64,
    },
    /// A note ends at or before its onset.
    #[error("note {index} ends at {offset_s} s, not after its onset {onset_s} s")]
    EmptyNote {
        /// Index of the note.
        index: usize,
        /// Its onset.
        onset_s: f64,
        /// Its offset.
        offset_s: f64,
    },
    /// A MIDI pitch above 127.
    #[error("note {index} has MIDI pitch {midi}; MIDI pitches are 0..=127")]
    InvalidMidi {
        /// Index of the note.
        index: usize,
        /// The pitch.
        midi: u8,
    },
    /// A note of `double_stops` ends at or before its onset, has a pitch above 127, or
    /// starts before the one listed before it.
    #[error("double_stops[{index}]: {problem}")]
    InvalidDoubleStop {
        /// Index in `double_stops`.
        index: usize,
        /// What is wrong, and the values.
        problem: String,
    },
    /// The arousal curve's rate is not positive and finite.
    #[error("arousal rate {rate_hz} Hz is not a positive finite number (DEAM curves are 2 Hz)")]
    InvalidArousalRate {
        /// The rate given.
        rate_hz: f64,
    },
    /// An arousal value outside [-1, 1] (use [`crate::ArousalCurve::clamped`] to clip).
    #[error("arousal[{index}] = {value} lies outside [-1, 1]; rescale the curve or use ArousalCurve::clamped")]
    ArousalOutOfRange {
        /// Index of the value.
        index: usize,
        /// The value.
        value: f32,
    },
    /// The dynamics list does not have one level per note.
    #[error("dynamics has {got} levels for {expected} notes; give one level per note")]
    DynamicsLength {
        /// Number of notes.
        expected: usize,
        /// Number of levels.
        got: usize,
    },
    /// A dynamics level outside [0, 1].
    #[error("dynamics[{index}] = {value} lies outside [0, 1]")]
    DynamicsOutOfRange {
        /// Index of the note.
        index: usize,
        /// The level.
        value: f32,
    },
    /// A note gives some but not all of `string`, `position`, `finger`.
    #[error(
        "a note gives only part of its fingering; give all of string, position and finger, or none"
    )]
    PartialFingering,
    /// Text that is not a time signature.
    #[error("\"{0}\" is not a time signature: write it as N/D, e.g. 3/4 or 6/8 (N 1..=32, D 1, 2, 4, 8, 16 or 32)")]
    TimeSignature(String),
}

/// A performance (or `analysis.json`) file that could not be read.
#[derive(Debug, thiserror::Error)]
pub enum PerformanceFileError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The file is not a valid performance JSON.
    #[error("{path}: not a performance JSON: {reason}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// What is wrong (serde's message, with line and column).
        reason: String,
    },
}

/// A MIDI file that could not be used.
#[cfg(feature = "midi")]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{path}: {reason}")]
pub struct MidiError {
    /// The file (or `<memory>`).
    pub path: PathBuf,
    /// What is wrong and what to do.
    pub reason: String,
}
