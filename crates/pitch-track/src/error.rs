//! The error type of `pitch-track`.

/// Everything that can go wrong while tracking pitch or segmenting notes.
#[derive(Debug, thiserror::Error)]
pub enum PitchError {
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
    #[error("invalid pitch-tracking configuration: {0}")]
    InvalidConfig(String),
    /// Two series that must have the same length do not.
    #[error("{what}: lengths differ ({left} vs {right}); pass series on the same time grid")]
    LengthMismatch {
        /// Which series.
        what: &'static str,
        /// Length of the first.
        left: usize,
        /// Length of the second.
        right: usize,
    },
    /// A spectrogram computation in `dsp-mel` failed.
    #[error(transparent)]
    Dsp(#[from] dsp_mel::DspError),
}

/// `Result` with [`PitchError`].
pub type Result<T> = std::result::Result<T, PitchError>;

/// Index of the first NaN or infinity in `samples`.
pub(crate) fn first_non_finite(samples: &[f32]) -> Option<usize> {
    samples.iter().position(|s| !s.is_finite())
}
