//! The fingering flags shared by `analyze` and `generate`: planner, style knobs, *sul*
//! passages and MIDI octave transposition.

use clap::{Args, ValueEnum};
use violin_skeleton::{FingeringStyle, PipelineBuilder, PlannerKind, SulSpan, ViolinString};

/// Fingering planner.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PlannerArg {
    /// Learned from ten violinists' fingerings (TNUA dataset; default).
    Learned,
    /// Viterbi over the physical model with hand-set costs.
    #[value(alias = "viterbi")]
    Optimal,
    /// The original greedy rule.
    Greedy,
}

/// Open strings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OpenStrings {
    /// As the planner likes them.
    Neutral,
    /// Wherever they are within reach.
    Prefer,
    /// Only where nothing else plays the note.
    Avoid,
}

/// Hand positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Positions {
    /// As the planner likes them.
    Neutral,
    /// As low on the neck as the notes allow.
    Low,
    /// Higher on the neck.
    High,
}

/// Fingering flags.
#[derive(Debug, Clone, Args)]
pub struct FingeringArgs {
    /// Fingering planner (`viterbi` is another name for `optimal`; `--fingering` is another
    /// name for this flag).
    #[arg(long, visible_alias = "fingering", value_enum, default_value_t = PlannerArg::Learned)]
    pub planner: PlannerArg,
    /// Open strings: neutral, prefer or avoid (optimal and learned planners).
    #[arg(long, value_enum, default_value_t = OpenStrings::Neutral)]
    pub open_strings: OpenStrings,
    /// Hand positions: neutral, low or high (optimal and learned planners).
    #[arg(long, value_enum, default_value_t = Positions::Neutral)]
    pub positions: Positions,
    /// Keep a passage on one string: `G` (the whole piece) or `G@12.5-20` (notes starting
    /// from 12.5 s to 20 s); strings G, D, A, E; repeatable.
    #[arg(long, value_parser = parse_sul)]
    pub sul: Vec<SulSpan>,
    /// MIDI input: move notes outside the violin's range (G3..A7) by octaves instead of
    /// refusing the file.
    #[arg(long)]
    pub transpose_into_range: bool,
}

impl Default for FingeringArgs {
    fn default() -> Self {
        FingeringArgs {
            planner: PlannerArg::Learned,
            open_strings: OpenStrings::Neutral,
            positions: Positions::Neutral,
            sul: Vec::new(),
            transpose_into_range: false,
        }
    }
}

/// Parses `G` or `G@12.5-20`.
pub fn parse_sul(text: &str) -> Result<SulSpan, String> {
    let (name, range) = match text.split_once('@') {
        Some((n, r)) => (n, Some(r)),
        None => (text, None),
    };
    let string = match name.trim().to_ascii_uppercase().as_str() {
        "G" | "1" => ViolinString::G,
        "D" | "2" => ViolinString::D,
        "A" | "3" => ViolinString::A,
        "E" | "4" => ViolinString::E,
        other => return Err(format!("`{other}` is not a string: use G, D, A or E")),
    };
    let (from_s, to_s) = match range {
        None => (0.0, f64::INFINITY),
        Some(r) => {
            let (a, b) = r.split_once('-').ok_or_else(|| {
                format!("`{r}`: give the passage as FROM-TO seconds, e.g. G@12.5-20")
            })?;
            let num = |s: &str| {
                s.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite() && *v >= 0.0)
                    .ok_or_else(|| format!("`{s}` is not a time in seconds"))
            };
            let (a, b) = (num(a)?, num(b)?);
            if b <= a {
                return Err(format!("the passage {a}-{b} s ends before it starts"));
            }
            (a, b)
        }
    };
    Ok(SulSpan {
        string,
        from_s,
        to_s,
    })
}

impl FingeringArgs {
    /// Sets the planner, style, passages and MIDI transposition on a pipeline builder.
    pub fn apply(&self, builder: PipelineBuilder) -> PipelineBuilder {
        let mut style = FingeringStyle::default();
        match self.open_strings {
            OpenStrings::Neutral => {}
            OpenStrings::Prefer => {
                style.open_string = FingeringStyle::prefer_open_strings().open_string
            }
            OpenStrings::Avoid => {
                style.open_string = FingeringStyle::avoid_open_strings().open_string
            }
        }
        match self.positions {
            Positions::Neutral => {}
            Positions::Low => style.position = FingeringStyle::low_positions().position,
            Positions::High => style.position = FingeringStyle::high_positions().position,
        }
        let mut builder = builder
            .planner(match self.planner {
                PlannerArg::Learned => PlannerKind::Learned,
                PlannerArg::Optimal => PlannerKind::Optimal,
                PlannerArg::Greedy => PlannerKind::Greedy,
            })
            .fingering_style(style)
            .transpose_into_range(self.transpose_into_range);
        for s in &self.sul {
            builder = builder.sul(s.string, s.from_s, s.to_s);
        }
        builder
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sul_flags_parse() {
        let s = parse_sul("g").unwrap();
        assert_eq!((s.string, s.from_s), (ViolinString::G, 0.0));
        assert!(s.to_s.is_infinite());
        let s = parse_sul("D@12.5-20").unwrap();
        assert_eq!((s.string, s.from_s, s.to_s), (ViolinString::D, 12.5, 20.0));
        assert!(parse_sul("X").is_err());
        assert!(parse_sul("G@20-10").is_err());
        assert!(parse_sul("G@a-b").is_err());
    }
}
