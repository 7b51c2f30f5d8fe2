//! [`Chunking`]: how `Pipeline::analyze_file` and `generate_file` cut a long recording, and
//! the length limit they check while reading.

use std::path::Path;

use crate::error::{Error, Result};

/// How a long recording is cut.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chunking {
    /// Seconds each chunk owns (default 120).
    pub core_s: f64,
    /// Seconds of context analysed on each side of a chunk and then dropped (default 10).
    pub margin_s: f64,
}

impl Default for Chunking {
    fn default() -> Self {
        Self {
            core_s: 120.0,
            margin_s: 10.0,
        }
    }
}

/// Refuses a recording of `duration_s` (announced, or read so far) over `max_s`; a container
/// without a length (or with a wrong one) is checked as it is read.
pub(crate) fn check_length(max_s: Option<f64>, path: &Path, duration_s: f64) -> Result<()> {
    match max_s {
        Some(max) if duration_s > max + 0.5 => Err(Error::TooLong {
            source_name: path.display().to_string(),
            duration_s,
            max_s: max,
        }),
        _ => Ok(()),
    }
}
