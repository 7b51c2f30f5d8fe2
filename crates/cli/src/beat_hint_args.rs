//! `--time-signature` and `--tempo-bpm`: what the user knows about a recording's beat.

use std::path::Path;

use clap::Args;
use violin_skeleton::{
    hint_tempo_range_around, BeatHints, BeatMethod, PipelineBuilder, TimeSignature,
    HINT_TEMPO_RANGE_BPM,
};

use crate::error::CliError;
use crate::motion_of::is_midi;
use crate::weight_args::BeatArg;

/// The beat hints of the commands that analyse audio.
#[derive(Debug, Clone, Default, Args)]
pub struct BeatHintArgs {
    /// The written time signature, e.g. 3/4, 4/4, 6/8 or 2/2: the bar length is then taken
    /// from it instead of guessed (audio, learned beat tracker).
    #[arg(long, value_name = "N/D")]
    pub time_signature: Option<TimeSignature>,
    /// The tempo at the notated beat (a quarter in 4/4, a dotted quarter in 6/8): one value
    /// (then ±15 %) or a range, e.g. 120 or 100-140 (audio, learned beat tracker).
    #[arg(long, value_name = "BPM|LO-HI", value_parser = parse_tempo_range)]
    pub tempo_bpm: Option<(f64, f64)>,
}

impl BeatHintArgs {
    /// The hints as the facade takes them.
    pub fn hints(&self) -> BeatHints {
        BeatHints {
            time_signature: self.time_signature,
            tempo_range_bpm: self.tempo_bpm,
        }
    }

    /// Refuses, before any file is read, hints the run cannot use (the facade's
    /// [`BeatHints::check_for`]: `--beats classic`, a bar longer than the tracker follows)
    /// and hints for a MIDI `input` (a folder's MIDI files are refused one by one).
    pub fn check(&self, beats: BeatArg, input: &Path) -> Result<(), CliError> {
        if self.hints().is_empty() {
            return Ok(());
        }
        let method = match beats {
            BeatArg::Learned => BeatMethod::Learned,
            BeatArg::Classic => BeatMethod::Classic,
        };
        if let Err(e) = self.hints().check_for(method) {
            return Err(CliError::Usage(format!(
                "--time-signature/--tempo-bpm: {e}"
            )));
        }
        if is_midi(input) {
            return Err(CliError::Usage(format!(
                "{}: --time-signature and --tempo-bpm apply to audio; a MIDI file's own tempo map and time signatures are used, so drop them",
                input.display()
            )));
        }
        Ok(())
    }

    /// Sets the hints on a pipeline builder.
    pub fn apply(&self, builder: PipelineBuilder) -> PipelineBuilder {
        builder.beat_hints(self.hints())
    }
}

/// `115` → 100–132.25 (±15 %), `100-140` → 100–140; both ends within the facade's range.
pub fn parse_tempo_range(text: &str) -> Result<(f64, f64), String> {
    let (min, max) = HINT_TEMPO_RANGE_BPM;
    let bad = || {
        format!(
            "\"{text}\" is not a tempo: give beats per minute (e.g. 120) or a range (e.g. 100-140), within {min}-{max}"
        )
    };
    let number = |t: &str| t.trim().parse::<f64>().map_err(|_| bad());
    let (lo, hi) = match text.split_once('-') {
        Some((a, b)) => (number(a)?, number(b)?),
        None => hint_tempo_range_around(number(text)?),
    };
    let hints = BeatHints {
        tempo_range_bpm: Some((lo, hi)),
        ..BeatHints::default()
    };
    hints.check().map(|()| (lo, hi)).map_err(|_| bad())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tempo_hints_parse_as_a_value_or_a_range() {
        let (lo, hi) = parse_tempo_range("115").unwrap();
        assert!((lo - 100.0).abs() < 1e-9 && (hi - 132.25).abs() < 1e-9);
        assert_eq!(parse_tempo_range(" 60 - 80 ").unwrap(), (60.0, 80.0));
        for bad in [
            "", "fast", "80-60", "0", "-5", "60-", "5-30", "300-500", "NaN", "inf",
        ] {
            let e = parse_tempo_range(bad).unwrap_err();
            assert!(e.contains("not a tempo"), "{bad}: {e}");
        }
    }
}
