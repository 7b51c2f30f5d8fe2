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
    /// Beat or downbeat activations are unusable (lengths differ, not probabilities).
    #[error("invalid beat activations: {0}")]
    InvalidActivation(String),
    /// The spectrogram computation failed.
    #[error(transparent)]
    Dsp(#[from] dsp_mel::DspError),
}

/// `Result` with [`BeatError`].
pub type Result<T> = std::result::Result<T, BeatError>;

/// Index of the first NaN or infinity. Blocks are screened branch-free first (`v · 0` is
/// 0 for a finite `v` and NaN otherwise, and the lane sums vectorise), so a clean
/// recording costs one vectorised pass instead of a test and branch per sample.
pub(crate) fn first_non_finite(x: &[f32]) -> Option<usize> {
    const BLOCK: usize = 1024;
    for (b, block) in x.chunks(BLOCK).enumerate() {
        let mut acc = [0.0f32; 8];
        let lanes = block.chunks_exact(8);
        let tail: f32 = lanes.remainder().iter().map(|v| v * 0.0).sum();
        for c in lanes {
            for k in 0..8 {
                acc[k] += c[k] * 0.0;
            }
        }
        if (acc.iter().sum::<f32>() + tail).is_nan() {
            return block
                .iter()
                .position(|v| !v.is_finite())
                .map(|i| b * BLOCK + i);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_first_bad_sample_in_any_block_position() {
        let mut x = vec![0.5f32; 5000];
        assert_eq!(first_non_finite(&x), None);
        for (i, bad) in [
            (0, f32::NAN),
            (1023, f32::INFINITY),
            (4999, f32::NEG_INFINITY),
        ] {
            x[i] = bad;
            assert_eq!(first_non_finite(&x), Some(i));
            x[i] = 0.5;
        }
        x[3000] = f32::NAN;
        x[4000] = f32::INFINITY;
        assert_eq!(first_non_finite(&x), Some(3000));
    }
}
