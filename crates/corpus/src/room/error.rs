//! [`RoomError`]: what can go wrong in the recording chain.

/// What can go wrong in the recording chain.
#[derive(Debug, thiserror::Error)]
pub enum RoomError {
    /// The sample rate is unusable.
    #[error("recording: sample rate {0} Hz is outside 8000..=384000")]
    SampleRate(u32),
    /// The convolution failed (an internal buffer-length bug; please report it).
    #[error("room convolution: {0}")]
    Convolution(String),
    /// An encoder program is not installed.
    #[error("`{tool}` is not installed or not on PATH: install it (Debian: apt-get install lame vorbis-tools) or build the corpus with --no-augment")]
    EncoderMissing {
        /// `lame` or `oggenc`.
        tool: &'static str,
    },
    /// An encoder program failed.
    #[error("`{tool}` failed: {reason}")]
    Encoder {
        /// `lame` or `oggenc`.
        tool: &'static str,
        /// Its exit status and message.
        reason: String,
    },
}
