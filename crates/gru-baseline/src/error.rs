//! The error type of `gru-baseline`.

use std::path::PathBuf;

/// Everything that can go wrong building, training, loading or running the Method 1 network.
#[derive(Debug, thiserror::Error)]
pub enum GruError {
    /// An input array has the wrong shape.
    #[error("{what}: expected shape {expected}, got {got}")]
    Shape {
        /// Which input.
        what: String,
        /// The expected shape, e.g. "(frames, 128)".
        expected: String,
        /// The shape received.
        got: String,
    },
    /// An input has no frames.
    #[error("{0}: no frames; give at least one 1/30 s frame of audio")]
    Empty(String),
    /// An input contains NaN or infinity.
    #[error("{what}: non-finite value at index {index}; clean the input (NaN/inf) before calling")]
    NonFinite {
        /// Which input.
        what: String,
        /// Flat index of the first bad value.
        index: usize,
    },
    /// A weights file cannot be used.
    #[error("{path}: {reason}")]
    Weights {
        /// The file (`<pretrained>` for the embedded weights).
        path: PathBuf,
        /// What is wrong and what to do.
        reason: String,
    },
    /// A training-data folder cannot be used.
    #[error("{path}: {reason}")]
    Data {
        /// The file or folder.
        path: PathBuf,
        /// What is wrong and what to do.
        reason: String,
    },
    /// A setting is out of range.
    #[error("invalid configuration: {0}")]
    Config(String),
    /// Audio decoding or the mel spectrogram failed.
    #[error(transparent)]
    Dsp(#[from] dsp_mel::DspError),
    /// A motion could not be built or read.
    #[error(transparent)]
    Skeleton(#[from] skeleton::SkeletonError),
    /// A checkpoint could not be written or read, or training diverged (shared code of
    /// `net-core`).
    #[error(transparent)]
    Store(#[from] net_core::StoreError),
    /// A tensor operation failed (a bug or an exhausted machine; please report it).
    #[error("tensor operation failed: {0}")]
    Candle(#[from] candle_core::Error),
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, GruError>;
