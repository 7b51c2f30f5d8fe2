//! The error type of `corpus`.

use std::path::PathBuf;

use crate::render::RenderError;

/// What can go wrong making or reading a corpus.
#[derive(Debug, thiserror::Error)]
pub enum CorpusError {
    /// Rendering failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The generated performance did not validate (a bug: please report the seed).
    #[error("performance: {0}")]
    Performance(String),
    /// A file could not be written or read.
    #[error("{path}: {reason}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What went wrong and what to do.
        reason: String,
    },
    /// A MIDI file could not be used.
    #[error("{path}: {reason}")]
    Midi {
        /// The file (or `<memory>`).
        path: PathBuf,
        /// What is wrong and what to do.
        reason: String,
    },
    /// A setting is out of range.
    #[error("{0}")]
    Config(String),
}
