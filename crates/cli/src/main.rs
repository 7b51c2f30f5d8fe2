//! `violin-skeleton`: from a solo violin recording to a violinist skeleton animation.
//!
//! Exit codes: 0 success; 1 the input, output or machine failed (one line on stderr says
//! which file, what is wrong and what to do); 2 the command line is wrong.

mod error;
mod features;
mod output;

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
    /// Write the networks' mel inputs (mel30: 30 fps × 128, mel2: 2 fps × 64) as float32 .npy.
    Features(features::FeaturesArgs),
}

/// Prints progress and summaries on stderr unless `--quiet`.
pub struct Reporter {
    quiet: bool,
}

impl Reporter {
    /// A summary line.
    pub fn line(&self, text: &str) {
        if !self.quiet {
            eprintln!("{text}");
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let report = Reporter { quiet: cli.quiet };
    let result: Result<(), CliError> = match &cli.command {
        Command::Features(args) => features::run(args, &report),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
