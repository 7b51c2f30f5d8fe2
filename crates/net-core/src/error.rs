//! The crate's error type.

use std::path::PathBuf;

/// Everything net-core can fail with.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// A tensor operation failed (a shape or dtype bug, or out of memory).
    #[error("tensor operation failed: {0}")]
    Candle(#[from] candle_core::Error),
    /// A file could not be read or written.
    #[error("{path}: {reason}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong and what to do.
        reason: String,
    },
    /// A weights or checkpoint file is not one this build can use (wrong network, version,
    /// shapes, truncated, non-finite values).
    #[error("{path}: not usable weights: {reason}")]
    Weights {
        /// The file (a placeholder such as `<embedded …>` for embedded defaults).
        path: PathBuf,
        /// What does not match, and what to do.
        reason: String,
    },
    /// A value cannot be stored (e.g. metadata that does not serialise).
    #[error("invalid configuration: {0}")]
    Config(String),
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, StoreError>;

impl StoreError {
    /// A [`StoreError::Io`] for `path`.
    pub fn io(path: impl Into<PathBuf>, reason: impl std::fmt::Display) -> Self {
        StoreError::Io {
            path: path.into(),
            reason: reason.to_string(),
        }
    }

    /// A [`StoreError::Weights`] for `path`.
    pub fn weights(path: impl Into<PathBuf>, reason: impl std::fmt::Display) -> Self {
        StoreError::Weights {
            path: path.into(),
            reason: reason.to_string(),
        }
    }
}
