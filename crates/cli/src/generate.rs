//! `violin-skeleton generate`: a recording (or MIDI file) in, motion out.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, ValueEnum};
use violin_skeleton::skeleton::formats::OpenPoseOptions;
use violin_skeleton::{Canvas, Method, Motion, MotionFormat, Pipeline, PipelineBuilder};

use crate::batch::BatchArgs;
use crate::beat_hint_args::BeatHintArgs;
use crate::contract::{check_outputs, named, refuse_stdout_folder};
use crate::error::CliError;
use crate::fingering_args::FingeringArgs;
use crate::limits::InputLimits;
pub use crate::motion_of::{is_midi, make_motion, with_input, Made, MethodArg};
use crate::preview::{check_preview_name, write_preview, SoundSource};
pub use crate::weight_args::{AnalysisWeights, NetworkWeights};
use crate::Reporter;

/// Motion file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OutFormat {
    /// Motion JSON (2-D, 3-D and instrument tracks).
    Json,
    /// A folder of OpenPose `*_keypoints.json` files (BODY_25), for pose-conditioned generators.
    Openpose,
    /// One row per frame, `joint_x, joint_y` columns.
    Csv,
    /// float32 (frames, 20).
    Npy,
    /// BVH of the 3-D rig (Blender: File → Import → Motion Capture (.bvh)).
    Bvh,
    /// glTF 2.0 binary of the 3-D rig: animated node hierarchy (Blender: File → Import → glTF).
    Glb,
}

impl OutFormat {
    /// The format a path's extension names (a path without one is an OpenPose folder).
    pub fn from_path(path: &Path) -> Option<Self> {
        match path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
        {
            None => Some(OutFormat::Openpose),
            Some(e) => match e.as_str() {
                "json" => Some(OutFormat::Json),
                "csv" => Some(OutFormat::Csv),
                "npy" => Some(OutFormat::Npy),
                "bvh" => Some(OutFormat::Bvh),
                "glb" => Some(OutFormat::Glb),
                _ => None,
            },
        }
    }

    /// The file extension this format writes (`None`: a folder).
    pub fn extension(self) -> Option<&'static str> {
        match self {
            OutFormat::Json => Some("json"),
            OutFormat::Csv => Some("csv"),
            OutFormat::Npy => Some("npy"),
            OutFormat::Bvh => Some("bvh"),
            OutFormat::Glb => Some("glb"),
            OutFormat::Openpose => None,
        }
    }
}

/// Arguments of `generate`.
#[derive(Debug, Args)]
#[command(
    after_help = "Examples:\n  violin-skeleton generate take1.wav -o take1.json\n  violin-skeleton generate take1.flac -o take1_openpose --format openpose --preview take1.html\n  violin-skeleton generate piece.mid -o piece.bvh\n  violin-skeleton generate jig.wav -o jig.json --time-signature 6/8 --tempo-bpm 100-130\n  violin-skeleton generate take1.wav -o take1.glb --preview take1.mp4\n  violin-skeleton generate take1.wav -o m1.json --method gru"
)]
pub struct GenerateArgs {
    /// Audio (wav, flac, mp3, ogg) or MIDI (.mid, .midi); or a folder: every such file
    /// under it, in parallel, outputs mirrored under `-o` (batch mode).
    pub input: PathBuf,
    /// Output file, or folder for `--format openpose` (batch mode: the output folder).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Output format (default: from the output's extension; none → openpose).
    #[arg(long, value_enum)]
    pub format: Option<OutFormat>,
    /// Motion method.
    #[arg(long, value_enum, default_value_t = MethodArg::Rules)]
    pub method: MethodArg,
    /// Fingering planner and style.
    #[command(flatten)]
    pub fingering: FingeringArgs,
    /// Input limits.
    #[command(flatten)]
    pub limits: InputLimits,
    /// What is known of the beat.
    #[command(flatten)]
    pub beat_hints: BeatHintArgs,
    /// Also write a preview: `.gif`, `.html` (a player with the sound: audio up to 2 MiB
    /// embedded, larger audio linked beside the page, MIDI notes synthesized in the browser)
    /// or `.mp4` (H.264 with the audio as AAC; needs ffmpeg; a MIDI input gives a silent video).
    #[arg(long)]
    pub preview: Option<PathBuf>,
    /// Put the audio in the HTML player whatever its size (one self-contained page).
    #[arg(long)]
    pub embed_audio: bool,
    /// OpenPose picture size WIDTHxHEIGHT: the performer (body, hands, violin, bow) is
    /// fitted and centred at one scale for the whole clip, with 5 % margins.
    #[arg(long, default_value = "1280x720")]
    pub canvas: String,
    /// Also write the analysis (f0, notes, bow changes, beats, arousal) as JSON.
    #[arg(long)]
    pub analysis_out: Option<PathBuf>,
    /// Network weight files (default: the embedded ones).
    #[command(flatten)]
    pub weights: NetworkWeights,
    /// Batch mode (a folder as input).
    #[command(flatten)]
    pub batch: BatchArgs,
}

/// Share of each side left free around the performer in OpenPose frames.
pub const CANVAS_MARGIN: f64 = violin_skeleton::skeleton::canvas::DEFAULT_CANVAS_MARGIN;

/// Parses `--canvas WxH` (a usage error when it is not a size or too small for a person).
pub fn parse_canvas(text: &str) -> Result<Canvas, CliError> {
    text.parse::<Canvas>()
        .map_err(|e| CliError::Usage(format!("--canvas: {e}")))
}

/// Writes `motion` to `path` in `format`; OpenPose frames are fitted to `canvas`.
pub fn write_motion(
    motion: &Motion,
    path: &Path,
    format: OutFormat,
    canvas: Canvas,
) -> Result<(), CliError> {
    match format {
        OutFormat::Json => motion.write(path, MotionFormat::Json)?,
        OutFormat::Csv => motion.write(path, MotionFormat::Csv)?,
        OutFormat::Npy => motion.write(path, MotionFormat::Npy)?,
        OutFormat::Openpose => motion
            .fitted_to_canvas(canvas, CANVAS_MARGIN)
            .write_openpose(path, &OpenPoseOptions::named_after(path))?,
        OutFormat::Bvh => violin_skeleton::motion_synth::bvh::write_bvh_file(motion, path)
            .map_err(violin_skeleton::Error::from)?,
        OutFormat::Glb => motion.write(path, MotionFormat::Glb)?,
    }
    Ok(())
}

/// The pipeline the method, fingering and weight flags describe.
pub fn pipeline_for(
    method: MethodArg,
    fingering: &FingeringArgs,
    weights: &NetworkWeights,
) -> Pipeline {
    pipeline_builder_for(method, fingering, weights).build()
}

/// [`pipeline_for`]'s builder, for commands that set more.
pub fn pipeline_builder_for(
    method: MethodArg,
    fingering: &FingeringArgs,
    weights: &NetworkWeights,
) -> PipelineBuilder {
    let mut builder = fingering.apply(Pipeline::builder().method(match method {
        MethodArg::Rules => Method::Rules,
        MethodArg::Gru => Method::Gru,
    }));
    builder = weights.analysis.apply(builder);
    if let Some(p) = &weights.gru_weights {
        builder = builder.gru_weights(p);
    }
    builder
}

/// Runs `generate`.
pub fn run(args: &GenerateArgs, report: &Reporter) -> Result<(), CliError> {
    args.beat_hints
        .check(args.weights.analysis.beats, &args.input)?;
    if matches!(args.method, MethodArg::Gru) && !args.beat_hints.hints().is_empty() {
        return Err(CliError::Usage(
            "--time-signature and --tempo-bpm steer the analysis of --method rules; Method 1 (gru) does not track beats, so drop them"
                .into(),
        ));
    }
    if args.input.is_dir() {
        return run_folder(args, report);
    }
    let format = match args.format.or_else(|| OutFormat::from_path(&args.output)) {
        Some(f) => f,
        None => {
            return Err(CliError::Usage(format!(
                "-o {}: cannot tell the format from the extension; use .json, .csv, .npy, .bvh, .glb, a folder name, or --format",
                args.output.display()
            )))
        }
    };
    check_generate_paths(args, format)?;
    let canvas = parse_canvas(&args.canvas)?;
    let pipeline = pipeline_of(args);
    let t0 = Instant::now();
    let bar = report.progress(1, "analysing (audio seconds)");
    let made = make_motion(
        &pipeline,
        &args.input,
        args.method,
        args.analysis_out.as_deref(),
        args.preview.is_some(),
        |done_s, total_s| {
            if let Some(t) = total_s {
                bar.set_length(t.ceil() as u64);
            }
            bar.set_position(done_s.floor() as u64);
        },
    )?;
    bar.finish_and_clear();
    let Made {
        motion,
        summary,
        stages: timings_line,
        midi_notes,
    } = made;
    let t_write = Instant::now();
    write_motion(&motion, &args.output, format, canvas)?;
    let mut preview_note = None;
    if let Some(p) = &args.preview {
        let source = if is_midi(&args.input) {
            SoundSource::Notes(&midi_notes)
        } else {
            SoundSource::Audio {
                path: &args.input,
                embed: args.embed_audio,
            }
        };
        preview_note = write_preview(&motion, p, source)?;
    }
    report.line(&format!(
        "{}: {} → {} frames ({:.1} s at 30 fps, {format:?}) written to {} in {:.2} s",
        args.input.display(),
        summary,
        motion.len(),
        motion.duration_s(),
        args.output.display(),
        t0.elapsed().as_secs_f64()
    ));
    if let Some(note) = preview_note {
        report.line(&note);
    }
    if !timings_line.is_empty() {
        report.line(&format!(
            "  stages: {timings_line}, writing {:.3} s",
            t_write.elapsed().as_secs_f64()
        ));
    }
    Ok(())
}

/// The pipeline the method, fingering, weight and limit flags describe.
fn pipeline_of(args: &GenerateArgs) -> Pipeline {
    let builder = pipeline_builder_for(args.method, &args.fingering, &args.weights);
    args.beat_hints.apply(args.limits.apply(builder)).build()
}

/// `generate DIR -o OUTDIR`: every music file under `DIR` (see [`crate::batch`]).
fn run_folder(args: &GenerateArgs, report: &Reporter) -> Result<(), CliError> {
    for (flag, given) in [
        ("--preview", args.preview.is_some()),
        ("--analysis-out", args.analysis_out.is_some()),
    ] {
        if given {
            return Err(CliError::Usage(format!(
                "{flag}: not available with a folder as input; run generate on one file for it"
            )));
        }
    }
    crate::batch::check_output_folder(&args.input, &args.output)?;
    let format = args.format.unwrap_or(OutFormat::Json);
    if matches!(format, OutFormat::Bvh | OutFormat::Glb) && matches!(args.method, MethodArg::Gru) {
        return Err(CliError::Usage(format!(
            "--format {}: it needs the 3-D rig, which only --method rules makes",
            format.extension().unwrap_or_default()
        )));
    }
    let canvas = parse_canvas(&args.canvas)?;
    let plan = crate::batch::plan(&args.input, &args.output, format.extension())?;
    let pipeline = pipeline_of(args);
    crate::batch::run_batch(
        "generate",
        &args.input,
        &args.output,
        plan,
        &args.batch,
        report,
        |input, output| {
            let made = make_motion(&pipeline, input, args.method, None, false, |_, _| {})?;
            write_motion(&made.motion, output, format, canvas)
        },
    )
}

/// The output contract and the flag checks of `generate`, before anything is read or written.
fn check_generate_paths(args: &GenerateArgs, format: OutFormat) -> Result<(), CliError> {
    if format == OutFormat::Openpose {
        refuse_stdout_folder(
            named("-o", &args.output),
            "OpenPose output",
            "give a folder name, or --format json|csv|npy|bvh|glb for one file",
        )?;
    }
    if let Some(p) = &args.preview {
        check_preview_name(p)?;
    }
    if matches!(format, OutFormat::Bvh | OutFormat::Glb) && matches!(args.method, MethodArg::Gru) {
        let (ext, name) = if format == OutFormat::Bvh {
            ("bvh", "BVH")
        } else {
            ("glb", "glTF")
        };
        return Err(CliError::Usage(format!(
            "-o .{ext}: {name} needs the 3-D rig, which only --method rules makes; use --format json, csv, npy or openpose with --method gru"
        )));
    }
    let mut inputs = vec![named("input", &args.input)];
    inputs.extend(args.weights.analysis.inputs());
    if let Some(p) = &args.weights.gru_weights {
        inputs.push(named("--gru-weights", p));
    }
    let mut outputs = vec![named("-o", &args.output)];
    if let Some(p) = &args.preview {
        outputs.push(named("--preview", p));
    }
    if let Some(p) = &args.analysis_out {
        outputs.push(named("--analysis-out", p));
    }
    check_outputs(&inputs, &outputs)
}
