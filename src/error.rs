//! The facade's error: every crate's error, wrapped, so callers match on one type.

/// Anything the pipeline can fail with.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Loading or analysing audio.
    #[error(transparent)]
    Audio(#[from] dsp_mel::DspError),
    /// Pitch tracking.
    #[error(transparent)]
    Pitch(#[from] pitch_track::PitchError),
    /// Beat tracking.
    #[error(transparent)]
    Beat(#[from] beat_track::BeatError),
    /// Fingering.
    #[error(transparent)]
    Fingering(#[from] fingering::FingeringError),
    /// Building the performance.
    #[error(transparent)]
    Performance(#[from] performance::PerformanceError),
    /// Motion synthesis.
    #[error(transparent)]
    Synth(#[from] motion_synth::SynthError),
    /// Motion files.
    #[error(transparent)]
    Skeleton(#[from] skeleton::SkeletonError),
    /// A MIDI file that cannot be used.
    #[cfg(feature = "midi")]
    #[error(transparent)]
    Midi(#[from] performance::MidiError),
    /// A performance or analysis file that cannot be read.
    #[error(transparent)]
    PerformanceFile(#[from] performance::PerformanceFileError),
    /// The recording has no notes to play.
    #[error("{0}: no notes were found; is this a solo violin recording (not silence or noise)?")]
    NoNotes(String),
    /// The recording is too short to show any playing.
    #[error("{source_name}: the recording is {duration_s:.2} s long; at least {min_s} s of audio is needed to see bowing")]
    TooShort {
        /// The file, or "the recording" for audio in memory.
        source_name: String,
        /// Its length in seconds.
        duration_s: f64,
        /// The shortest length accepted, in seconds.
        min_s: f64,
    },
    /// The recording is longer than the pipeline accepts.
    #[error("{source_name}: lasts {duration_s:.0} s, more than the {max_s:.0} s accepted; cut it or raise --max-duration")]
    TooLong {
        /// The file.
        source_name: String,
        /// Its length in seconds (or how far it was read).
        duration_s: f64,
        /// The longest length accepted, in seconds.
        max_s: f64,
    },
    /// A network failed or its weights do not fit.
    #[error("{0}")]
    Network(String),
    /// A time-signature or tempo hint that cannot be used.
    #[error("{0}")]
    BeatHint(String),
}

/// `Result` with the facade's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
