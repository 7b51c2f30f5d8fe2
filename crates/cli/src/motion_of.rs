//! One input's motion: the core of `generate`, run per file by batch mode too.

use std::path::Path;
use std::time::Instant;

use clap::ValueEnum;
use violin_skeleton::{Motion, Pipeline};

use crate::error::CliError;

/// Motion method.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum MethodArg {
    /// Method 2: analysis → performance → rules (default).
    Rules,
    /// Method 1: the GRU baseline.
    Gru,
}

/// `true` for a `.mid` or `.midi` file name.
pub fn is_midi(path: &Path) -> bool {
    path.extension().is_some_and(|e| {
        matches!(
            e.to_string_lossy().to_ascii_lowercase().as_str(),
            "mid" | "midi"
        )
    })
}

/// What [`make_motion`] made from one input.
pub struct Made {
    /// The motion.
    pub motion: Motion,
    /// One line: notes, bow changes, tempo.
    pub summary: String,
    /// Stage timings (audio with `--method rules`; empty otherwise).
    pub stages: String,
    /// The MIDI file's notes, when asked for (for a preview's sound).
    pub midi_notes: Vec<violin_skeleton::Note>,
}

/// The motion of one recording or MIDI file (the core of `generate`, also run per file by
/// batch mode); the analysis goes to `analysis_out` when given.
pub fn make_motion(
    pipeline: &Pipeline,
    input: &Path,
    method: MethodArg,
    analysis_out: Option<&Path>,
    keep_midi_notes: bool,
    on_progress: impl FnMut(f64, Option<f64>),
) -> Result<Made, CliError> {
    let write_analysis = |p: &Path, analysis: &violin_skeleton::Analysis| {
        crate::output::write_atomically(p, |w| {
            serde_json::to_writer(w, analysis).map_err(|e| e.to_string())
        })
    };
    if is_midi(input) {
        if let Some(p) = analysis_out {
            let analysis = pipeline
                .analyze_midi_file(input)
                .map_err(|e| with_input(e, input))?;
            write_analysis(p, &analysis)?;
        }
        let perf = pipeline
            .performance_from_midi(input)
            .map_err(|e| with_input(e, input))?;
        let motion = violin_skeleton::motion_synth::synthesize(&perf, pipeline.synth_config())
            .map_err(violin_skeleton::Error::from)?;
        let summary = format!(
            "{} notes, {} bow changes (MIDI)",
            perf.notes().len(),
            perf.bow_changes_s().len()
        );
        let midi_notes = if keep_midi_notes {
            perf.notes().to_vec()
        } else {
            Vec::new()
        };
        return Ok(Made {
            motion,
            summary,
            stages: String::new(),
            midi_notes,
        });
    }
    match method {
        MethodArg::Rules => {
            let (analysis, timings) = pipeline
                .analyze_file_timed(input, on_progress)
                .map_err(|e| with_input(e, input))?;
            if let Some(p) = analysis_out {
                write_analysis(p, &analysis)?;
            }
            let t_synth = Instant::now();
            let motion = pipeline
                .generate_from_analysis(&analysis)
                .map_err(|e| with_input(e, input))?;
            Ok(Made {
                motion,
                summary: format!(
                    "{} notes, {} bow changes, {:.0} bpm",
                    analysis.notes.len(),
                    analysis.bow_changes_s.len(),
                    analysis.tempo_bpm
                ),
                stages: format!(
                    "{timings}, synthesis {:.3} s",
                    t_synth.elapsed().as_secs_f64()
                ),
                midi_notes: Vec::new(),
            })
        }
        MethodArg::Gru => {
            let motion = pipeline
                .generate_file(input, on_progress)
                .map_err(|e| with_input(e, input))?;
            Ok(Made {
                motion,
                summary: "Method 1 (GRU)".to_string(),
                stages: String::new(),
                midi_notes: Vec::new(),
            })
        }
    }
}

/// Names the input file in a "no notes" error.
pub fn with_input(e: violin_skeleton::Error, input: &Path) -> CliError {
    match e {
        violin_skeleton::Error::NoNotes(_) => {
            CliError::Pipeline(violin_skeleton::Error::NoNotes(input.display().to_string()))
        }
        violin_skeleton::Error::TooShort {
            duration_s, min_s, ..
        } => CliError::Pipeline(violin_skeleton::Error::TooShort {
            source_name: input.display().to_string(),
            duration_s,
            min_s,
        }),
        other => CliError::Pipeline(other),
    }
}
