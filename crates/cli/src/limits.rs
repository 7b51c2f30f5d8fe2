//! `--max-duration`: the longest input `generate` and `analyze` accept.

use clap::Args;
use violin_skeleton::PipelineBuilder;

/// The input limits of the commands that read music.
#[derive(Debug, Clone, Default, Args)]
pub struct InputLimits {
    /// Refuse inputs longer than this many seconds (audio by its announced or read length,
    /// MIDI by when its last note ends). Default: audio of any length (analysed in pieces),
    /// MIDI up to 3600 s.
    #[arg(long, value_name = "SECONDS", value_parser = clap::value_parser!(u32).range(1..))]
    pub max_duration: Option<u32>,
}

impl InputLimits {
    /// Sets the limits on a pipeline builder.
    pub fn apply(&self, builder: PipelineBuilder) -> PipelineBuilder {
        match self.max_duration {
            Some(s) => builder.max_duration_s(s),
            None => builder,
        }
    }
}
