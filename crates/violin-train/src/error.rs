//! The crate's error: every error of the crates it drives, wrapped with their own messages,
//! plus malformed labelled folders.

use std::path::PathBuf;

/// Everything loading, training or evaluating can fail with.
#[derive(Debug, thiserror::Error)]
pub enum TrainError {
    /// A labelled dataset folder (corpus or URMP layout) is missing files or malformed.
    #[error("{path}: {reason}")]
    Dataset {
        /// The file or folder.
        path: PathBuf,
        /// What is wrong and what to do.
        reason: String,
    },
    /// The bow-change network or its data.
    #[error(transparent)]
    Bowing(#[from] bowing_net::NetError),
    /// The beat network or its data.
    #[error(transparent)]
    BeatNet(#[from] beat_net::BeatNetError),
    /// The arousal network or its data.
    #[error(transparent)]
    Emotion(#[from] emotion_net::EmotionError),
    /// The Method 1 network or its data.
    #[error(transparent)]
    Gru(#[from] gru_baseline::GruError),
    /// Reading or measuring a skeleton (OpenPose folders, bowing attacks).
    #[error(transparent)]
    Pose(#[from] pose_preproc::PosePreprocError),
    /// Pitch tracking or its scores.
    #[error(transparent)]
    Pitch(#[from] pitch_track::PitchError),
    /// Motion synthesis of a reference performance.
    #[error(transparent)]
    Synth(#[from] motion_synth::SynthError),
    /// Motion files.
    #[error(transparent)]
    Skeleton(#[from] skeleton::SkeletonError),
    /// Audio decoding or the mel spectrogram.
    #[error(transparent)]
    Audio(#[from] dsp_mel::DspError),
    /// The pipeline (analysis and motion of a recording).
    #[error(transparent)]
    Pipeline(#[from] violin_skeleton::Error),
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, TrainError>;
