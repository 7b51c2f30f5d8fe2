//! [`Chunking`]: how `Pipeline::analyze_file` and `generate_file` cut a long recording.

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
