//! The error type of `beat-track`.

/// Everything that can go wrong while tracking onsets, tempo, beats and downbeats.
#[derive(Debug, thiserror::Error)]
pub enum BeatError {
    /// The audio has no samples.
    #[error("audio has no samples; pass a recording of at least one frame")]
    EmptyAudio,
    /// A sample is NaN or infinite.
    #[error("sample {index} is not a finite number (NaN or infinity); the audio is damaged")]
    NonFinite {
        /// Index of the first bad sample.
        index: usize,
    },
    /// A configuration value is out of range.
    #[error("invalid beat-tracking configuration: {0}")]
    InvalidConfig(String),
    /// The spectrogram computation failed.
    #[error(transparent)]
    Dsp(#[from] dsp_mel::DspError),
}

/// `Result` with [`BeatError`].
pub type Result<T> = std::result::Result<T, BeatError>;

/// Index of the first NaN or infinity.
pub(crate) fn first_non_finite(x: &[f32]) -> Option<usize> {
    x.iter().position(|v| !v.is_finite())
}
