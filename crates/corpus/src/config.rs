//! What a corpus build is asked for: [`CorpusConfig`] and [`RendererChoice`].

use std::path::PathBuf;

use crate::etude::EtudeConfig;

/// Which renderer(s) make the audio.
#[derive(Debug, Clone, PartialEq)]
pub enum RendererChoice {
    /// The built-in bowed-string synthesizer only.
    Builtin,
    /// A SoundFont only.
    Soundfont(PathBuf),
    /// Half and half: item `i` uses the SoundFont when `(i + i / 10)` is odd, so every split
    /// (test = indices ending in 3, validation = in 7) gets both renderers.
    Mix(PathBuf),
    /// Every source of [`crate::violins::VIOLINS`] (SoundFonts read from this folder), split
    /// by violin and by work ([`crate::schedule`]).
    Many(PathBuf),
}

impl RendererChoice {
    /// "builtin", "soundfont" or "mix".
    pub fn name(&self) -> &'static str {
        match self {
            RendererChoice::Builtin => "builtin",
            RendererChoice::Soundfont(_) => "soundfont",
            RendererChoice::Mix(_) => "mix",
            RendererChoice::Many(_) => "many",
        }
    }
}

/// What to build.
#[derive(Debug, Clone, PartialEq)]
pub struct CorpusConfig {
    /// Total audio to make, in minutes (items are about `etude.target_s` long).
    pub minutes: f64,
    /// Corpus seed: the same seed gives identical files.
    pub seed: u64,
    /// Renderer(s).
    pub renderer: RendererChoice,
    /// Apply seeded augmentation (reverb, gain, noise, tuning, 22.05–48 kHz).
    pub augment: bool,
    /// The étude generator's settings.
    pub etude: EtudeConfig,
    /// Repertoire scores (`scripts/export_repertoire.py` output) mixed with the études
    /// (many-violin corpora only).
    pub repertoire: Option<PathBuf>,
    /// A violin training never hears, for validation (many-violin corpora only): a GUS
    /// patch (`.pat`, e.g. FreePats' `Tone_000/040_Violin.pat`) or an SF2 with GM program
    /// 40. When set, only the validation items are written, each rendered with this violin
    /// instead of the one drawn for it (the scores, performances and labels are the same as
    /// in the corpus built without it).
    pub validation_violin: Option<PathBuf>,
    /// Another training violin (many-violin corpora only): the same kinds of file as
    /// `validation_violin`, an SF2 with another GM program after a colon
    /// (`FluidR3_GM.sf2:41`, the viola), or a folder of per-note recordings (`A4.mp3`,
    /// `C#5.wav`, …; see `render::sample_dir_samples`). When set, only the training items
    /// are written, each rendered with this violin instead of the one drawn for it (same
    /// scores, performances and labels), so that a network can be trained on both corpora.
    /// Not with `validation_violin`.
    pub training_violin: Option<PathBuf>,
}

impl Default for CorpusConfig {
    fn default() -> Self {
        Self {
            minutes: 10.0,
            seed: 0,
            renderer: RendererChoice::Builtin,
            augment: true,
            etude: EtudeConfig::default(),
            repertoire: None,
            validation_violin: None,
            training_violin: None,
        }
    }
}
