//! `violin-skeleton`: from a solo violin recording to a violinist skeleton animation.
//!
//! Exit codes: 0 success; 1 the input, output or machine failed (one line on stderr says
//! which file, what is wrong and what to do); 2 the command line is wrong.

mod analyze;
mod batch;
mod beat_hint_args;
mod contract;
mod corpus_cmd;
mod demo;
mod error;
mod evaluate;
mod features;
mod fingering_args;
mod generate;
mod limits;
mod motion_of;
mod output;
mod pose_labels;
mod preview;
mod render;
mod train;
mod train_args;
mod train_gru;
mod train_io;
mod weight_args;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use error::CliError;

/// Turn a solo violin recording into a violinist skeleton animation (30 fps).
#[derive(Debug, Parser)]
#[command(name = "violin-skeleton", version, about, long_about = None)]
#[command(
    after_help = "Exit codes: 0 success, 1 failure (one line on stderr says why), 2 bad command line."
)]
struct Cli {
    /// Print nothing but errors.
    #[arg(short, long, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run the whole pipeline on the shipped demo clip and write ./demo-out/ (motion, OpenPose, BVH, glTF, previews).
    Demo(demo::DemoArgs),
    /// A recording (wav/flac/mp3/ogg) or MIDI file in, violinist motion out (json, openpose, csv, npy, bvh, glb).
    Generate(generate::GenerateArgs),
    /// Write the networks' mel inputs (mel30: 30 fps × 128, mel2: 2 fps × 64) as float32 .npy.
    Features(features::FeaturesArgs),
    /// Make a synthetic violin corpus with exact labels (audio, notes, bow changes, beats, arousal, motion).
    Corpus(corpus_cmd::CorpusArgs),
    /// OpenPose JSON directory → cleaned 10-joint skeleton + bow-change frames and seconds
    /// (labels.json); bowing arm and bow axis found in the data, any camera and frame rate.
    PoseLabels(pose_labels::PoseLabelsArgs),
    /// Analyse a recording or MIDI file: f0, notes with fingering, bow changes, beats, downbeats, meter, arousal (analysis.json).
    Analyze(analyze::AnalyzeArgs),
    /// Draw a motion as an animated GIF, PNG frames, an HTML player or an MP4 with the audio; or convert it to .glb or to OpenPose frames fitted to a canvas.
    Render(render::RenderArgs),
    /// Every SPEC §10 measure on a labelled corpus or URMP folder: a table, and a JSON report.
    Evaluate(evaluate::EvaluateArgs),
    /// Train the bow-change CNN, the arousal CRNN or the Method 1 GRU (corpus, URMP or DEAM folder).
    Train(train_args::TrainArgs),
}

/// Prints progress and summaries on stderr unless `--quiet`.
pub struct Reporter {
    quiet: bool,
}

impl Reporter {
    /// A progress bar on stderr for `total` steps (hidden with `--quiet` or when stderr is
    /// not a terminal).
    pub fn progress(&self, total: u64, what: &str) -> indicatif::ProgressBar {
        if self.quiet {
            return indicatif::ProgressBar::hidden();
        }
        let bar = indicatif::ProgressBar::new(total);
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{msg} [{bar:30}] {pos}/{len} ({elapsed}, eta {eta})",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message(what.to_string());
        bar
    }

    /// A summary line.
    pub fn line(&self, text: &str) {
        if !self.quiet {
            eprintln!("{text}");
        }
    }
}

/// candle runs each element-wise op (a bias add, say) across every core behind a spinning
/// barrier; the pipeline already keeps both cores busy (pitch tracking beside the networks),
/// so outside training those ops stay on the calling thread unless `CANDLE_NUM_THREADS` says
/// otherwise. Measured on 3 minutes of audio: generate's median 0.935 → 0.895 s wall, CPU
/// time about 10 % lower, output unchanged. Called before any thread is started.
fn keep_candle_elementwise_ops_on_one_thread(command: &Command) {
    if !matches!(command, Command::Train(_)) && std::env::var_os("CANDLE_NUM_THREADS").is_none() {
        std::env::set_var("CANDLE_NUM_THREADS", "1");
    }
}

fn main() -> ExitCode {
    // A codec library that panics on a damaged file is turned into an error naming the file
    // (dsp-mel's guard); its panic message would be a second, confusing stderr line.
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if !violin_skeleton::dsp_mel::inside_decoder_guard() {
            default_hook(info)
        }
    }));
    let cli = Cli::parse();
    keep_candle_elementwise_ops_on_one_thread(&cli.command);
    let report = Reporter { quiet: cli.quiet };
    let result: Result<(), CliError> = match &cli.command {
        Command::Demo(args) => demo::run(args, &report),
        Command::Generate(args) => generate::run(args, &report),
        Command::Features(args) => features::run(args, &report),
        Command::Corpus(args) => corpus_cmd::run(args, &report),
        Command::PoseLabels(args) => pose_labels::run(args, &report),
        Command::Analyze(args) => analyze::run(args, &report),
        Command::Render(args) => render::run(args, &report),
        Command::Train(args) => train::run(args, &report),
        Command::Evaluate(args) => evaluate::run(args, &report),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
