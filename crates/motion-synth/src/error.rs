//! Errors of motion synthesis.

use performance::PerformanceError;

use std::path::PathBuf;

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
    /// A performance JSON file could not be read.
    #[error(transparent)]
    PerformanceFile(#[from] performance::PerformanceFileError),
}

/// `Result` with [`SynthError`].
pub type Result<T> = std::result::Result<T, SynthError>;
