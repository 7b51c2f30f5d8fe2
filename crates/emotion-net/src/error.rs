//! The crate's error type.

use std::path::PathBuf;

/// Everything emotion-net can fail with.
#[derive(Debug, thiserror::Error)]
pub enum EmotionError {
    /// A data set folder or one of its files is missing or malformed.
    #[error("{path}: {reason}")]
    Data {
        /// The offending file or folder.
        path: PathBuf,
        /// What is wrong and what to do.
        reason: String,
    },
    /// An input array is unusable (empty, too short, NaN, wrong width).
    #[error("bad input: {0}")]
    Input(String),
    /// A configuration value is out of range.
    #[error("invalid configuration: {0}")]
    Config(String),
    /// A weights or checkpoint file could not be read, written or used.
    #[error(transparent)]
    Store(#[from] net_core::StoreError),
    /// A tensor operation failed.
    #[error("tensor operation failed: {0}")]
    Candle(#[from] candle_core::Error),
    /// Audio decoding or the mel spectrogram failed.
    #[error(transparent)]
    Dsp(#[from] dsp_mel::DspError),
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, EmotionError>;

impl EmotionError {
    /// An [`EmotionError::Data`] for `path`.
    pub fn data(path: impl Into<PathBuf>, reason: impl std::fmt::Display) -> Self {
        EmotionError::Data {
            path: path.into(),
            reason: reason.to_string(),
        }
    }

    /// A weights file that cannot be used ([`net_core::StoreError::Weights`]) for `path`.
    pub fn weights(path: impl Into<PathBuf>, reason: impl std::fmt::Display) -> Self {
        EmotionError::Store(net_core::StoreError::weights(path, reason))
    }
}

impl From<net_core::frames::InputError> for EmotionError {
    fn from(e: net_core::frames::InputError) -> Self {
        EmotionError::Input(e.0)
    }
}
