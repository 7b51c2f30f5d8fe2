//! Errors of skeleton-render.

use std::path::PathBuf;

/// What can go wrong drawing or writing a preview.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The motion has no frames.
    #[error("the motion has no frames; nothing to draw")]
    EmptyMotion,
    /// The motion's coordinates are all non-finite, so no picture can be framed.
    #[error("the motion has no finite coordinate to frame; check the motion file")]
    NothingToFrame,
    /// A render setting is unusable.
    #[error("invalid render configuration: {0}")]
    InvalidConfig(String),
    /// The audio's MIME type is not a plain `type/subtype`.
    #[error("audio MIME type {0:?} is not of the form type/subtype (e.g. audio/wav)")]
    InvalidMime(String),
    /// A file or folder could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// Writing to a stream failed.
    #[error("write failed: {0}")]
    Write(#[from] std::io::Error),
    /// The GIF encoder failed.
    #[error("GIF encoding failed: {0}")]
    Gif(String),
    /// The `ffmpeg` program (needed for MP4) is not installed.
    #[error("ffmpeg is not installed (not found on PATH); install it to write .mp4 (Debian/Ubuntu: apt-get install ffmpeg, macOS: brew install ffmpeg) or set FFMPEG=/path/to/ffmpeg")]
    FfmpegMissing,
    /// ffmpeg failed or the MP4 could not be written.
    #[error("MP4 encoding failed: {0}")]
    Ffmpeg(String),
    /// The PNG encoder failed.
    #[error("PNG encoding failed: {0}")]
    Png(String),
}

/// `Result` with [`RenderError`].
pub type Result<T> = std::result::Result<T, RenderError>;
