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
    /// An output could not be written.
    #[error("{path}: cannot write output: {reason}")]
    Output {
        /// The output path.
        path: PathBuf,
        /// What went wrong and what to do.
        reason: String,
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
