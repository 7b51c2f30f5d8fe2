//! Arousal-labelled recordings in memory, what training and evaluation take: a recording's
//! 2 fps mel spectrogram with arousal targets for a run of its frames, and the recordings by
//! split. Loading them from the synthetic corpus or DEAM is `violin-train`'s job.

use ndarray::Array2;

/// One recording with arousal targets for a run of its frames.
#[derive(Debug, Clone, PartialEq)]
pub struct ArousalTrack {
    /// A name for reports.
    pub name: String,
    /// `builtin`, `soundfont` or `deam`.
    pub group: String,
    /// 2 fps × 64 mel dB.
    pub mel_db: Array2<f32>,
    /// Frame of the first target.
    pub first_frame: usize,
    /// Targets for frames `first_frame ..` (as many as the audio has frames for).
    pub arousal: Vec<f32>,
}

/// Tracks by split.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ArousalSplits {
    /// Training tracks.
    pub train: Vec<ArousalTrack>,
    /// Validation tracks.
    pub val: Vec<ArousalTrack>,
    /// Test tracks.
    pub test: Vec<ArousalTrack>,
}
