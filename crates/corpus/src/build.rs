//! Building a whole corpus: items in parallel, each seeded on its own, then the manifest.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

pub use crate::config::{CorpusConfig, RendererChoice};
use crate::error::CorpusError;
use crate::item::{make_item, RendererKind};
use crate::layout::{write_atomic, write_item};
use crate::manifest::{Manifest, ManifestItem, Split, MANIFEST_VERSION};
use crate::render::{BowedStringSynth, Renderer, SoundFontRenderer};
use crate::stats::CorpusStats;
use net_core::rng::Rng;

/// Whether item `index` of a `mix` corpus uses the SoundFont: when `index + index / 10` is
/// odd, which alternates within every split (test and validation indices end in 3 and 7).
pub fn mix_uses_soundfont(index: usize) -> bool {
    (index + index / 10) % 2 == 1
}

/// Well-known places of Debian's General MIDI SoundFonts (SF2).
pub const SYSTEM_SOUNDFONTS: [&str; 3] = [
    "/usr/share/sounds/sf2/FluidR3_GM.sf2",
    "/usr/share/sounds/sf2/TimGM6mb.sf2",
    "/usr/share/sounds/sf2/default-GM.sf2",
];

/// The first system SoundFont that exists.
pub fn find_system_soundfont() -> Option<PathBuf> {
    SYSTEM_SOUNDFONTS
        .iter()
        .map(PathBuf::from)
        .find(|p| p.is_file())
}

/// Builds the corpus into `root`, calling `progress(done, total)` after each item.
///
/// ```no_run
/// use corpus::build::{build_corpus, CorpusConfig};
/// let manifest = build_corpus("corpus".as_ref(), &CorpusConfig::default(), &|_, _| {})?;
/// println!("{} items", manifest.items.len());
/// # Ok::<(), corpus::CorpusError>(())
/// ```
pub fn build_corpus(
    root: &Path,
    cfg: &CorpusConfig,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Manifest, CorpusError> {
    if !(cfg.minutes.is_finite() && cfg.minutes > 0.0 && cfg.minutes <= 10_000.0) {
        return Err(CorpusError::Config(format!(
            "--minutes {} must be between 0 and 10000",
            cfg.minutes
        )));
    }
    std::fs::create_dir_all(root).map_err(|e| CorpusError::Io {
        path: root.to_path_buf(),
        reason: format!("cannot create the corpus folder ({e})"),
    })?;
    if let RendererChoice::Many(sf2_dir) = &cfg.renderer {
        return crate::many::build_many(root, cfg, sf2_dir, progress);
    }
    let builtin = BowedStringSynth::default();
    let font = match &cfg.renderer {
        RendererChoice::Builtin | RendererChoice::Many(_) => None,
        RendererChoice::Soundfont(p) | RendererChoice::Mix(p) => {
            Some(SoundFontRenderer::from_file(p)?)
        }
    };
    let count = ((cfg.minutes * 60.0) / cfg.etude.target_s.max(1.0))
        .ceil()
        .max(1.0) as usize;
    let splits = Split::assign(count);
    let seeds = Rng::new(cfg.seed);
    let done = AtomicUsize::new(0);
    let entries: Vec<Result<(ManifestItem, performance::Timeline, String), CorpusError>> = (0
        ..count)
        .into_par_iter()
        .map(|i| {
            let (renderer, kind): (&dyn Renderer, RendererKind) = match (&cfg.renderer, &font) {
                (RendererChoice::Mix(_), Some(f)) if mix_uses_soundfont(i) => {
                    (f, RendererKind::Soundfont)
                }
                (RendererChoice::Soundfont(_), Some(f)) => (f, RendererKind::Soundfont),
                _ => (&builtin, RendererKind::Builtin),
            };
            let item = make_item(
                seeds.fork(i as u64).next_u64(),
                &cfg.etude,
                renderer,
                kind,
                cfg.augment,
            )?;
            write_item(root, i, &item)?;
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, count);
            let meter = item.time_signature.to_string();
            let entry = ManifestItem::of(
                i,
                &item,
                splits[i],
                crate::schedule::HeldOut::None,
                kind.name(),
                "audio.wav".into(),
            );
            Ok((entry, item.timeline, meter))
        })
        .collect();
    let entries = entries.into_iter().collect::<Result<Vec<_>, _>>()?;
    let stats = CorpusStats::of(entries.iter().map(|(_, t, m)| (t, m.as_str())));
    let manifest = Manifest {
        version: MANIFEST_VERSION,
        seed: cfg.seed,
        renderer: cfg.renderer.name().to_string(),
        items: entries.into_iter().map(|(e, _, _)| e).collect(),
        stats,
        violins: Vec::new(),
        skipped_scores: Vec::new(),
        double_stops_played: 0,
        chord_pitches_dropped: 0,
    };
    let json =
        serde_json::to_string_pretty(&manifest).map_err(|e| CorpusError::Config(e.to_string()))?;
    write_atomic(&root.join("manifest.json"), &json)?;
    Ok(manifest)
}
