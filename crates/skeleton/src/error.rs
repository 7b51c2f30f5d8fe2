//! The error type of `skeleton`.

use std::path::PathBuf;

/// What can go wrong building, reading or writing motion.
#[derive(Debug, thiserror::Error)]
pub enum SkeletonError {
    /// An array does not have the shape a motion track needs.
    #[error("wrong shape: expected {expected}, got {got:?}")]
    Shape {
        /// What was expected, in words (e.g. "(frames, 10, 2)").
        expected: String,
        /// The shape given.
        got: Vec<usize>,
    },
    /// The frame rate is not a positive finite number.
    #[error("invalid frame rate {0}; use a positive number of frames per second")]
    InvalidFps(f64),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A file's content is not what its format requires.
    #[error("{path}: {reason}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong, and where.
        reason: String,
    },
}

/// `Result` with [`SkeletonError`].
pub type Result<T> = std::result::Result<T, SkeletonError>;
