//! `violin-skeleton evaluate`: every SPEC §10 measure on a labelled folder.

use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, ValueEnum};
use violin_train::evaluate::{evaluate_dir_with_hints, LabelHints, SplitChoice};

use crate::error::CliError;
use crate::fingering_args::{FingeringArgs, PlannerArg};
use crate::generate::{pipeline_for, MethodArg, NetworkWeights};
use crate::output::write_atomically;
use crate::Reporter;

/// Which split to evaluate.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum SplitArg {
    /// The held-out test split.
    Test,
    /// The validation split.
    Val,
    /// The training split.
    Train,
    /// Every recording.
    All,
}

/// Arguments of `evaluate`.
#[derive(Debug, Args)]
#[command(
    after_help = "Measures: bow-change P/R/F1 (±2 frames; F1 also at ±3), raw pitch accuracy (±50 cents), note-onset F1 (±50 ms), beat and downbeat F (±70 ms), skeleton L1 (px, and in shoulder widths), jitter, bone-length variation, bow-range violations, beat alignment.\nA corpus folder (from `violin-skeleton corpus`) has every reference; a URMP folder (AuSep_K_vn_NAME.wav + openpose_K_vn_NAME/, with F0s_/Notes_ files when present) has bow changes from the skeleton, f0 and onsets.\n\nExamples:\n  violin-skeleton evaluate --data corpus\n  violin-skeleton evaluate --data corpus --method gru --report m1.json\n  violin-skeleton evaluate --data URMP --split all --report urmp.json"
)]
pub struct EvaluateArgs {
    /// A corpus folder or a URMP-layout folder.
    #[arg(long)]
    pub data: PathBuf,
    /// Which split (URMP tracks are split by index as the training loaders do).
    #[arg(long, value_enum, default_value_t = SplitArg::Test)]
    pub split: SplitArg,
    /// Motion method.
    #[arg(long, value_enum, default_value_t = MethodArg::Rules)]
    pub method: MethodArg,
    /// Write the whole report (per recording, per group, overall) as JSON here.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Only the first N recordings of the split.
    #[arg(long)]
    pub limit: Option<usize>,
    /// Network weight files (default: the embedded ones).
    #[command(flatten)]
    pub weights: NetworkWeights,
    /// Give each corpus item's labelled time signature, nominal tempo (±15 %) or both to
    /// the beat tracker, as a user who knows them would (`--time-signature`,
    /// `--tempo-bpm`); default: none, the blind analysis.
    #[arg(long, value_enum, default_value_t = HintsArg::None)]
    pub hints: HintsArg,
}

/// `evaluate --hints`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum HintsArg {
    /// No hints.
    None,
    /// The time signature.
    TimeSignature,
    /// The nominal tempo ±15 %.
    Tempo,
    /// Both.
    Both,
}

/// Runs `evaluate`.
pub fn run(args: &EvaluateArgs, report: &Reporter) -> Result<(), CliError> {
    if args.limit == Some(0) {
        return Err(CliError::Usage(
            "--limit 0: evaluate at least one recording".into(),
        ));
    }
    let fingering = FingeringArgs {
        planner: PlannerArg::Optimal,
        ..FingeringArgs::default()
    };
    let pipeline = pipeline_for(args.method, &fingering, &args.weights);
    let split = match args.split {
        SplitArg::Test => SplitChoice::Test,
        SplitArg::Val => SplitChoice::Val,
        SplitArg::Train => SplitChoice::Train,
        SplitArg::All => SplitChoice::All,
    };
    let t0 = Instant::now();
    let bar = report.progress(1, "evaluating (recordings)");
    let hints = match args.hints {
        HintsArg::None => LabelHints::None,
        HintsArg::TimeSignature => LabelHints::TimeSignature,
        HintsArg::Tempo => LabelHints::Tempo,
        HintsArg::Both => LabelHints::Both,
    };
    let result = evaluate_dir_with_hints(
        &pipeline,
        &args.data,
        split,
        args.limit,
        hints,
        |done, total| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        },
    )?;
    bar.finish_and_clear();
    if let Some(path) = &args.report {
        write_atomically(path, |w| {
            serde_json::to_writer_pretty(w, &result).map_err(|e| e.to_string())
        })?;
    }
    // The table is the command's output: stdout, even with --quiet.
    print!("{}", result.table());
    report.line(&format!(
        "{}: {} {} recordings ({} split, {:.1} min, method {}) evaluated in {:.1} s{}",
        args.data.display(),
        result.overall.recordings,
        result.layout,
        result.split,
        result.overall.duration_s / 60.0,
        result.method,
        t0.elapsed().as_secs_f64(),
        args.report.as_ref().map_or_else(String::new, |p| format!(
            "; report written to {}",
            p.display()
        ))
    ));
    Ok(())
}
