//! The crate's error type.

use std::path::PathBuf;

/// Everything beat-net can fail with.
#[derive(Debug, thiserror::Error)]
pub enum BeatNetError {
    /// A tensor operation failed (a shape or dtype bug, or out of memory).
    #[error("tensor operation failed: {0}")]
    Candle(#[from] candle_core::Error),
    /// An input array is unusable (empty, NaN, wrong width).
    #[error("bad input: {0}")]
    Input(String),
    /// A configuration value is out of range.
    #[error("invalid configuration: {0}")]
    Config(String),
    /// A weights file could not be read, written or used.
    #[error(transparent)]
    Store(#[from] net_core::StoreError),
    /// A data set item is unusable.
    #[error("{path}: {reason}")]
    Data {
        /// The offending file or folder.
        path: PathBuf,
        /// What is wrong and what to do.
        reason: String,
    },
}

impl From<net_core::frames::InputError> for BeatNetError {
    fn from(e: net_core::frames::InputError) -> Self {
        BeatNetError::Input(e.0)
    }
}

impl BeatNetError {
    /// A weights file that cannot be used, for `path`.
    pub fn weights(path: impl Into<PathBuf>, reason: impl std::fmt::Display) -> Self {
        BeatNetError::Store(net_core::StoreError::weights(path, reason))
    }
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, BeatNetError>;
