//! The violin sources a corpus renders with, which of them training may hear, and where
//! each comes from (name, licence).
//!
//! | source | what | licence | split |
//! |---|---|---|---|
//! | `builtin` | the additive bowed-string model, parameters drawn per item | ours | train |
//! | `waveguide` | a digital-waveguide bowed string (the physics of STK's `Bowed`, written anew) | ours | train |
//! | `fluidr3-violin` | FluidR3 GM program 40 (Debian `fluid-soundfont-gm`) | MIT | train |
//! | `fluidr3-fiddle` | FluidR3 GM program 110 | MIT | train |
//! | `fluidr3-strings` | FluidR3 GM program 48, a string section | MIT | train |
//! | `timgm6mb-violin` | TimGM6mb program 40 (Debian `timgm6mb-soundfont`) | GPL-2 | **held out** |
//! | `csound-violin` | Csound's `sf_GMbank` program 40 (Debian `csound-soundfont`) | LGPL-2.1+ | **held out** |
//!
//! Held-out sources render only test items: training and validation never hear them.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::CorpusError;
use crate::render::{BowedConfig, BowedStringSynth, Renderer, SoundFontRenderer, WaveguideViolin};
use net_core::rng::Rng;

/// Where Debian installs its SoundFonts.
pub const SYSTEM_SF2_DIR: &str = "/usr/share/sounds/sf2";

/// How a source makes sound.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SourceKind {
    /// The built-in bowed-string model.
    Builtin,
    /// The digital-waveguide bowed string.
    Waveguide,
    /// A SoundFont file (name inside the SoundFont folder) and GM program.
    SoundFont {
        /// File name, e.g. `FluidR3_GM.sf2`.
        file: &'static str,
        /// 0-based GM program.
        program: u8,
        /// The Debian package that installs it.
        package: &'static str,
    },
}

/// One violin source.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ViolinSpec {
    /// Name in the manifest.
    pub name: &'static str,
    /// How it sounds.
    pub kind: SourceKind,
    /// Licence of the samples or code.
    pub license: &'static str,
    /// Only test items use it.
    pub held_out: bool,
}

/// Every source, training ones first.
pub const VIOLINS: [ViolinSpec; 7] = [
    ViolinSpec {
        name: "builtin",
        kind: SourceKind::Builtin,
        license: "violin-skeleton's own code",
        held_out: false,
    },
    ViolinSpec {
        name: "waveguide",
        kind: SourceKind::Waveguide,
        license: "violin-skeleton's own code",
        held_out: false,
    },
    ViolinSpec {
        name: "fluidr3-violin",
        kind: SourceKind::SoundFont {
            file: "FluidR3_GM.sf2",
            program: 40,
            package: "fluid-soundfont-gm",
        },
        license: "MIT (FluidR3 by Frank Wen)",
        held_out: false,
    },
    ViolinSpec {
        name: "fluidr3-fiddle",
        kind: SourceKind::SoundFont {
            file: "FluidR3_GM.sf2",
            program: 110,
            package: "fluid-soundfont-gm",
        },
        license: "MIT (FluidR3 by Frank Wen)",
        held_out: false,
    },
    ViolinSpec {
        name: "fluidr3-strings",
        kind: SourceKind::SoundFont {
            file: "FluidR3_GM.sf2",
            program: 48,
            package: "fluid-soundfont-gm",
        },
        license: "MIT (FluidR3 by Frank Wen)",
        held_out: false,
    },
    ViolinSpec {
        name: "timgm6mb-violin",
        kind: SourceKind::SoundFont {
            file: "TimGM6mb.sf2",
            program: 40,
            package: "timgm6mb-soundfont",
        },
        license: "GPL-2 (Tim Brechbill, David Bolton)",
        held_out: true,
    },
    ViolinSpec {
        name: "csound-violin",
        kind: SourceKind::SoundFont {
            file: "sf_GMbank.sf2",
            program: 40,
            package: "csound-soundfont",
        },
        license: "LGPL-2.1+ (Csound)",
        held_out: true,
    },
];

/// What the manifest says about a source.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ViolinInfo {
    /// Name.
    pub name: String,
    /// File it was read from (empty for built-in sources).
    pub file: String,
    /// Licence.
    pub license: String,
    /// Only test items use it.
    pub held_out: bool,
}

/// The sources, loaded once per corpus build.
pub struct ViolinBank {
    specs: Vec<ViolinSpec>,
    fonts: Vec<Option<SoundFontRenderer>>,
    files: Vec<PathBuf>,
}

impl ViolinBank {
    /// Loads every source of [`VIOLINS`], reading SoundFonts from `sf2_dir`. A missing or
    /// unreadable SoundFont is refused with its path and the package that installs it.
    pub fn load(sf2_dir: &Path) -> Result<Self, CorpusError> {
        let mut fonts = Vec::new();
        let mut files = Vec::new();
        let mut loaded: Vec<(PathBuf, SoundFontRenderer)> = Vec::new();
        for spec in VIOLINS {
            match spec.kind {
                SourceKind::Builtin | SourceKind::Waveguide => {
                    fonts.push(None);
                    files.push(PathBuf::new());
                }
                SourceKind::SoundFont {
                    file,
                    program,
                    package,
                } => {
                    let path = sf2_dir.join(file);
                    let base = match loaded.iter().find(|(p, _)| *p == path) {
                        Some((_, f)) => f.clone(),
                        None => {
                            let f = SoundFontRenderer::from_file(&path).map_err(|e| {
                                CorpusError::Config(format!(
                                    "{e} (violin source {}: install the Debian package {package} \
                                     or pass --soundfont-dir)",
                                    spec.name
                                ))
                            })?;
                            loaded.push((path.clone(), f.clone()));
                            f
                        }
                    };
                    if !base.has_program(program) {
                        return Err(CorpusError::Config(format!(
                            "{}: has no GM program {program} (violin source {})",
                            path.display(),
                            spec.name
                        )));
                    }
                    fonts.push(Some(base.with_program(program)));
                    files.push(path);
                }
            }
        }
        Ok(Self {
            specs: VIOLINS.to_vec(),
            fonts,
            files,
        })
    }

    /// The sources' manifest entries.
    pub fn infos(&self) -> Vec<ViolinInfo> {
        self.specs
            .iter()
            .zip(&self.files)
            .map(|(s, f)| ViolinInfo {
                name: s.name.into(),
                file: f.display().to_string(),
                license: s.license.into(),
                held_out: s.held_out,
            })
            .collect()
    }

    /// Indices of the training sources (`held_out == false`) or of the held-out ones.
    pub fn indices(&self, held_out: bool) -> Vec<usize> {
        (0..self.specs.len())
            .filter(|&i| self.specs[i].held_out == held_out)
            .collect()
    }

    /// Source `index`'s spec.
    pub fn spec(&self, index: usize) -> Option<&ViolinSpec> {
        self.specs.get(index)
    }

    /// A renderer for source `index`; the built-in model's parameters are drawn from `rng`
    /// so that no two items play the same instrument.
    pub fn renderer(&self, index: usize, rng: &mut Rng) -> Option<Box<dyn Renderer + '_>> {
        let spec = self.specs.get(index)?;
        match self.fonts.get(index)? {
            Some(f) => Some(Box::new(f.clone())),
            None if spec.kind == SourceKind::Waveguide => {
                Some(Box::new(WaveguideViolin::default()))
            }
            None => Some(Box::new(BowedStringSynth {
                config: BowedConfig {
                    slur_glide_s: rng.uniform(0.015, 0.04),
                    vibrato_cents: (rng.uniform(5.0, 12.0), rng.uniform(15.0, 30.0)),
                    max_harmonics: rng.int(20, 48) as usize,
                    ..BowedConfig::default()
                },
            })),
        }
    }
}
