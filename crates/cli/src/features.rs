//! `violin-skeleton features`: the networks' mel inputs as float32 `.npy`.

use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, ValueEnum};
use ndarray_npy::WriteNpyExt;
use violin_skeleton::dsp_mel::{
    load_audio, resample, DbConfig, MelConfig, MelSpectrogram, DEFAULT_ANALYSIS_RATE_HZ,
};

use crate::contract::{check_outputs, named};
use crate::error::CliError;
use crate::output::write_atomically;
use crate::Reporter;

/// Which network input to compute.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum FeatureKind {
    /// 30 frames/s × 128 mel bands (bowing network, GRU baseline).
    Mel30,
    /// 2 frames/s × 64 mel bands (emotion network).
    Mel2,
}

/// Power or decibels.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Scale {
    /// `power_to_db(S, ref=1, amin=1e-10, top_db=80)`, as the networks use.
    Db,
    /// Mel power.
    Power,
}

/// Arguments of `features`.
#[derive(Debug, Args)]
#[command(
    after_help = "Examples:\n  violin-skeleton features take1.wav --kind mel30 -o take1_mel30.npy\n  violin-skeleton features take1.flac --kind mel2 --scale power --sample-rate native -o m.npy"
)]
pub struct FeaturesArgs {
    /// Audio file (wav, flac, mp3, ogg).
    pub input: PathBuf,
    /// Which features.
    #[arg(long, value_enum, default_value_t = FeatureKind::Mel30)]
    pub kind: FeatureKind,
    /// Values in dB or mel power.
    #[arg(long, value_enum, default_value_t = Scale::Db)]
    pub scale: Scale,
    /// Analysis sample rate in Hz, or `native` to keep the file's rate.
    #[arg(long, default_value_t = DEFAULT_ANALYSIS_RATE_HZ.to_string())]
    pub sample_rate: String,
    /// Output `.npy` (float32, shape frames × bands).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// Runs `features`.
pub fn run(args: &FeaturesArgs, report: &Reporter) -> Result<(), CliError> {
    let target_rate = parse_rate(&args.sample_rate)?;
    check_outputs(&[named("input", &args.input)], &[named("-o", &args.output)])?;
    let t0 = Instant::now();
    let mut audio = load_audio(&args.input)?;
    let decoded = t0.elapsed();
    let t1 = Instant::now();
    if let Some(rate) = target_rate {
        audio = resample(&audio, rate)?;
    }
    let resampled = t1.elapsed();
    let base = match args.kind {
        FeatureKind::Mel30 => MelConfig::bowing(),
        FeatureKind::Mel2 => MelConfig::emotion(),
    };
    let mel = MelSpectrogram::new(base.at_sample_rate(audio.sample_rate_hz()))?;
    let t2 = Instant::now();
    let features = match args.scale {
        Scale::Db => mel.compute_db(audio.samples(), &DbConfig::default())?,
        Scale::Power => mel.compute(audio.samples())?,
    };
    let computed = t2.elapsed();
    write_atomically(&args.output, |w| {
        features.write_npy(w).map_err(|e| e.to_string())
    })?;
    report.line(&format!(
        "{}: {:.1} s at {} Hz → {} frames × {} bands ({:.2} fps) written to {}",
        args.input.display(),
        audio.duration_s(),
        audio.sample_rate_hz(),
        features.nrows(),
        features.ncols(),
        mel.config().output_fps(),
        args.output.display()
    ));
    report.line(&format!(
        "timing: decode {:.1} ms, resample {:.1} ms, mel {:.1} ms, total {:.1} ms",
        decoded.as_secs_f64() * 1e3,
        resampled.as_secs_f64() * 1e3,
        computed.as_secs_f64() * 1e3,
        t0.elapsed().as_secs_f64() * 1e3
    ));
    Ok(())
}

fn parse_rate(text: &str) -> Result<Option<u32>, CliError> {
    if text.eq_ignore_ascii_case("native") {
        return Ok(None);
    }
    match text.parse::<u32>() {
        Ok(hz) if (1000..=768_000).contains(&hz) => Ok(Some(hz)),
        _ => Err(CliError::Usage(format!(
            "--sample-rate {text}: expected a rate in Hz between 1000 and 768000, or `native`"
        ))),
    }
}
