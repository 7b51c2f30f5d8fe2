//! The CLI's error: one readable line, and an exit code.

use std::path::PathBuf;

/// Exit code for a failure caused by the input, the output path or the machine.
pub const EXIT_FAILURE: u8 = 1;
/// Exit code for a command line that does not parse (clap's own convention).
pub const EXIT_USAGE: u8 = 2;

/// Everything a command can fail with.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Loading or analysing audio failed.
    #[error(transparent)]
    Dsp(#[from] violin_skeleton::dsp_mel::DspError),
    /// Making the corpus failed.
    #[error(transparent)]
    Corpus(#[from] corpus::CorpusError),
    /// Reading or cleaning an OpenPose directory failed.
    #[error(transparent)]
    PosePreproc(#[from] pose_preproc::PosePreprocError),
    /// Reading or writing a motion file failed.
    #[error(transparent)]
    Skeleton(#[from] violin_skeleton::skeleton::SkeletonError),
    /// Pitch tracking or note segmentation failed.
    #[error(transparent)]
    Pitch(#[from] violin_skeleton::pitch_track::PitchError),
    /// Onset, tempo or beat tracking failed.
    #[error(transparent)]
    Beat(#[from] violin_skeleton::beat_track::BeatError),
    /// Drawing a preview failed.
    #[error(transparent)]
    Render(#[from] violin_skeleton::skeleton_render::RenderError),
    /// Training or running the bowing network failed.
    #[error(transparent)]
    BowingNet(#[from] violin_skeleton::bowing_net::NetError),
    /// Training or running the Method 1 GRU failed.
    #[error(transparent)]
    GruBaseline(#[from] violin_skeleton::gru_baseline::GruError),
    /// The pipeline failed.
    #[error(transparent)]
    Pipeline(#[from] violin_skeleton::Error),
    /// Training or running the emotion network failed.
    #[error(transparent)]
    EmotionNet(#[from] violin_skeleton::emotion_net::EmotionError),
    /// Loading training data or evaluating failed.
    #[error(transparent)]
    Train(#[from] violin_train::TrainError),
    /// An output could not be written.
    #[error("{path}: cannot write output: {reason}")]
    Output {
        /// The output path.
        path: PathBuf,
        /// What went wrong and what to do.
        reason: String,
    },
    /// Some files of a batch failed (the others were written).
    #[error("{failed} of {files} files failed; each is listed with its reason in {}", summary.display())]
    BatchFailed {
        /// Files that failed.
        failed: usize,
        /// Files attempted.
        files: usize,
        /// The summary file.
        summary: PathBuf,
    },
    /// A flag value is not acceptable.
    #[error("{0}")]
    Usage(String),
}

impl CliError {
    /// The process exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Usage(_) => EXIT_USAGE,
            _ => EXIT_FAILURE,
        }
    }
}
