//! `violin-skeleton corpus`: the synthetic training/evaluation corpus.

use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, ValueEnum};
use corpus::build::{
    build_corpus, find_system_soundfont, CorpusConfig, RendererChoice, SYSTEM_SOUNDFONTS,
};

use crate::error::CliError;
use crate::Reporter;

/// Which renderer makes the audio.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum RendererArg {
    /// The built-in bowed-string synthesizer (no files needed).
    Builtin,
    /// A General MIDI SoundFont (program 40, violin).
    Soundfont,
    /// Half and half.
    Mix,
    /// Every violin source (built-in model and the Debian SoundFonts' violins, fiddle and
    /// string section), split by work and by violin; with --repertoire, real music too.
    Many,
}

/// Arguments of `corpus`.
#[derive(Debug, Args)]
#[command(
    after_help = "Examples:\n  violin-skeleton corpus --out corpus --hours 10 --seed 1 --renderer many --repertoire data/repertoire\n  violin-skeleton corpus --out corpus --minutes 60 --seed 1\n  violin-skeleton corpus --out corpus --minutes 60 --renderer mix --soundfont /usr/share/sounds/sf2/FluidR3_GM.sf2\n\nThe same seed gives identical files. Layout: see crates/corpus/README.md."
)]
pub struct CorpusArgs {
    /// Output folder (created if missing; items are replaced).
    #[arg(long)]
    pub out: PathBuf,
    /// Minutes of audio to make (default 10).
    #[arg(long, conflicts_with = "hours")]
    pub minutes: Option<f64>,
    /// Hours of audio to make (instead of --minutes).
    #[arg(long)]
    pub hours: Option<f64>,
    /// Corpus seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Renderer.
    #[arg(long, value_enum, default_value_t = RendererArg::Builtin)]
    pub renderer: RendererArg,
    /// SF2 SoundFont for `soundfont`/`mix` (default: a Debian GM SoundFont if installed).
    #[arg(long)]
    pub soundfont: Option<PathBuf>,
    /// Folder of the SoundFonts for `many` (FluidR3_GM.sf2, TimGM6mb.sf2, sf_GMbank.sf2).
    #[arg(long, default_value = corpus::violins::SYSTEM_SF2_DIR)]
    pub soundfont_dir: PathBuf,
    /// Repertoire scores for `many` (written by scripts/export_repertoire.py).
    #[arg(long)]
    pub repertoire: Option<PathBuf>,
    /// With `many`: write only the validation items, rendered with this violin instead
    /// of the drawn one — a GUS patch (.pat, e.g. Debian freepats'
    /// /usr/share/midi/freepats/Tone_000/040_Violin.pat), a WebAudioFont instrument (.js,
    /// e.g. webaudiofontdata's sound/0400_GeneralUserGS_sf2_file.js) or an SF2 with GM
    /// program 40 — so that choices can be checked on a violin training never hears.
    #[arg(long)]
    pub validation_violin: Option<PathBuf>,
    /// With `many`: write only the training items, rendered with this violin instead of
    /// the drawn one — the same kinds of file as --validation-violin, an SF2 with another
    /// GM program after a colon (FluidR3_GM.sf2:41, the viola), or a folder of one
    /// recording per note named by the note (A4.mp3, C#5.wav, …) — so that a network can be
    /// trained on one more violin (`train_strokes … --extra-train DIR`).
    #[arg(long, conflicts_with = "validation_violin")]
    pub training_violin: Option<PathBuf>,
    /// Render clean audio (no reverb, noise, gain or tuning changes; 22 050 Hz).
    #[arg(long)]
    pub no_augment: bool,
}

/// Runs `corpus`.
pub fn run(args: &CorpusArgs, report: &Reporter) -> Result<(), CliError> {
    let font = || -> Result<PathBuf, CliError> {
        args.soundfont.clone().or_else(find_system_soundfont).ok_or_else(|| {
            CliError::Usage(format!(
                "no SoundFont: pass --soundfont F.sf2, or install Debian's fluid-soundfont-gm (looked in {})",
                SYSTEM_SOUNDFONTS.join(", ")
            ))
        })
    };
    let renderer = match args.renderer {
        RendererArg::Builtin => RendererChoice::Builtin,
        RendererArg::Soundfont => RendererChoice::Soundfont(font()?),
        RendererArg::Mix => RendererChoice::Mix(font()?),
        RendererArg::Many => RendererChoice::Many(args.soundfont_dir.clone()),
    };
    if args.repertoire.is_some() && !matches!(args.renderer, RendererArg::Many) {
        return Err(CliError::Usage("--repertoire needs --renderer many".into()));
    }
    for (flag, set) in [
        ("--validation-violin", args.validation_violin.is_some()),
        ("--training-violin", args.training_violin.is_some()),
    ] {
        if set && !matches!(args.renderer, RendererArg::Many) {
            return Err(CliError::Usage(format!("{flag} needs --renderer many")));
        }
    }
    let minutes = match (args.minutes, args.hours) {
        (_, Some(h)) if !(h.is_finite() && h > 0.0) => {
            return Err(CliError::Usage(format!(
                "--hours {h}: give a positive number of hours, e.g. --hours 10"
            )))
        }
        (_, Some(h)) => h * 60.0,
        (Some(m), None) if !(m.is_finite() && m > 0.0) => {
            return Err(CliError::Usage(format!(
                "--minutes {m}: give a positive number of minutes, e.g. --minutes 10"
            )))
        }
        (Some(m), None) => m,
        (None, None) => 10.0,
    };
    let cfg = CorpusConfig {
        minutes,
        repertoire: args.repertoire.clone(),
        validation_violin: args.validation_violin.clone(),
        training_violin: args.training_violin.clone(),
        seed: args.seed,
        renderer,
        augment: !args.no_augment,
        ..CorpusConfig::default()
    };
    let t0 = Instant::now();
    let bar = report.progress(0, "rendering");
    let manifest = build_corpus(&args.out, &cfg, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })?;
    bar.finish_and_clear();
    let s = &manifest.stats;
    report.line(&format!(
        "{}: {} items, {:.1} min of audio ({}) in {:.1} s; {:.0} notes/min, {:.0} % of onsets are bow changes",
        args.out.display(),
        manifest.items.len(),
        s.minutes,
        manifest.renderer,
        t0.elapsed().as_secs_f64(),
        s.notes_per_minute,
        100.0 * s.bow_change_share_of_onsets
    ));
    Ok(())
}
