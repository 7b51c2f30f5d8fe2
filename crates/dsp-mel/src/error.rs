//! The error type of `dsp-mel`.

use std::path::PathBuf;

/// Everything that can go wrong while loading audio, computing features or filtering.
///
/// Every variant that concerns a file names it, says what is wrong and (through its
/// message) what to do about it.
#[derive(Debug, thiserror::Error)]
pub enum DspError {
    /// The path does not exist.
    #[error("{path}: file not found; check the path")]
    NotFound {
        /// The path that was asked for.
        path: PathBuf,
    },
    /// The path is a directory, not an audio file.
    #[error("{path}: is a directory; pass an audio file (wav, flac, mp3, ogg)")]
    IsDirectory {
        /// The path that was asked for.
        path: PathBuf,
    },
    /// The file has zero bytes.
    #[error("{path}: file is empty (0 bytes); re-export the recording")]
    EmptyFile {
        /// The path that was asked for.
        path: PathBuf,
    },
    /// The container or codec is not one we can read (or the bytes are not audio at all).
    #[error("{path}: not a supported audio file ({reason}); use wav, flac, mp3 or ogg/vorbis")]
    Unsupported {
        /// The path that was asked for.
        path: PathBuf,
        /// What the decoder said.
        reason: String,
    },
    /// The container was recognised but its data could not be decoded.
    #[error("{path}: corrupt audio data ({reason}); re-export or convert the file")]
    Corrupt {
        /// The path that was asked for.
        path: PathBuf,
        /// What the decoder said.
        reason: String,
    },
    /// The file decoded to zero samples.
    #[error("{path}: contains no audio samples; check that the recording is not empty")]
    NoSamples {
        /// The path that was asked for.
        path: PathBuf,
    },
    /// A decoded (or given) sample is NaN or infinite.
    #[error("{source_name}: sample {index} is not a finite number (NaN or infinity); the audio is damaged")]
    NonFinite {
        /// The file, or `"<memory>"` for samples passed in directly.
        source_name: String,
        /// Index of the first bad sample (mono, after mixdown).
        index: usize,
    },
    /// Reading the file failed at the operating-system level.
    #[error("{path}: cannot read ({source})")]
    Io {
        /// The path that was asked for.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// Audio given in memory has no samples.
    #[error("audio has no samples")]
    EmptyAudio,
    /// A sample rate of zero, or one the resampler rejects.
    #[error("invalid sample rate {0} Hz; use a rate between 1 Hz and 768 kHz")]
    InvalidSampleRate(u32),
    /// The resampler failed.
    #[error("resampling failed: {0}")]
    Resample(String),
    /// A configuration value is out of range.
    #[error("invalid configuration: {0}")]
    InvalidConfig(String),
    /// A signal is too short for the requested operation.
    #[error("signal of {len} samples is too short: this operation needs more than {needed}")]
    TooShort {
        /// Length of the given signal.
        len: usize,
        /// The length that must be exceeded.
        needed: usize,
    },
    /// A signal passed to a filter contains NaN or infinity.
    #[error("input value {index} is not a finite number (NaN or infinity)")]
    NonFiniteInput {
        /// Index of the first bad value.
        index: usize,
    },
}

/// `Result` with [`DspError`].
pub type Result<T> = std::result::Result<T, DspError>;
