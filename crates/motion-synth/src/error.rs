//! Errors of motion synthesis.

use std::path::PathBuf;

/// What is wrong with a [`crate::Performance`]: every check of [`crate::Performance::new`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PerformanceError {
    /// The duration is zero, negative or not finite.
    #[error("duration {duration_s} s is not a positive finite number of seconds")]
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
}

/// Everything motion synthesis can fail with.
#[derive(Debug, thiserror::Error)]
pub enum SynthError {
    /// The performance is invalid.
    #[error("invalid performance: {0}")]
    Performance(#[from] PerformanceError),
    /// Fingering could not be planned.
    #[error("fingering: {0}")]
    Fingering(#[from] fingering::FingeringError),
    /// Building or writing the motion failed.
    #[error(transparent)]
    Skeleton(#[from] skeleton::SkeletonError),
    /// A configuration value is unusable.
    #[error("invalid synthesis configuration: {0}")]
    InvalidConfig(String),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// Writing to a stream failed.
    #[error("write failed: {0}")]
    Write(#[from] std::io::Error),
    /// A performance JSON file could not be parsed.
    #[error("{path}: not a performance JSON: {reason}")]
    PerformanceFile {
        /// The file.
        path: PathBuf,
        /// What is wrong (serde's message, with line and column).
        reason: String,
    },
}

/// `Result` with [`SynthError`].
pub type Result<T> = std::result::Result<T, SynthError>;
