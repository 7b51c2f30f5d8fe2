//! Building a many-violin corpus: études and repertoire excerpts, every violin source, split
//! by work and by violin ([`crate::schedule`]), in parallel, each item seeded on its own.

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use crate::config::CorpusConfig;
use crate::error::CorpusError;
use crate::etude::generate;
use crate::item::{make_score_item, RendererKind};
use crate::layout::{write_atomic, write_item};
use crate::manifest::{Manifest, ManifestItem, Split, MANIFEST_VERSION};
use crate::render::{Renderer, SoundFontRenderer};
use crate::schedule::{plan_item, HeldOut, ItemPlan, Music, WorksBySplit};
use crate::score::Score;
use crate::stats::CorpusStats;
use crate::violins::{SourceKind, ViolinBank, ViolinInfo};
use net_core::rng::Rng;
use performance::Timeline;

/// The score an item plays: an étude's or a repertoire excerpt (an excerpt with fewer than
/// four notes, e.g. a long rest, becomes an étude instead).
fn score_of(plan: &mut ItemPlan, scores: &[Score], cfg: &CorpusConfig) -> Score {
    if let Music::Excerpt {
        score,
        first_bar,
        bars,
    } = plan.music
    {
        if let Some(s) = scores.get(score) {
            let ex = s.excerpt(first_bar, bars);
            if ex.notes.len() >= 4 {
                let mut ex = ex;
                ex.id = format!("{} bars {}-{}", s.id, first_bar + 1, first_bar + bars);
                return ex;
            }
        }
        let seed = (score as u64) << 32 | first_bar as u64;
        plan.music = Music::Etude(seed);
        plan.held_out = match plan.held_out {
            HeldOut::Repertoire => HeldOut::None,
            HeldOut::Both => HeldOut::Violin,
            h => h,
        };
    }
    let seed = match plan.music {
        Music::Etude(seed) => seed,
        Music::Excerpt { .. } => 0,
    };
    generate(seed, &cfg.etude).to_score(&format!("etude/{seed}"))
}

/// What item `i` plays and with which violin: its plan, score, violin index and the seed of
/// [`make_score_item`]. Drawn the same way for counting and for building.
struct ItemDraw {
    plan: ItemPlan,
    score: Score,
    violin: usize,
    rng: Rng,
    item_seed: u64,
}

/// The inputs every item is drawn from.
struct Draws<'a> {
    cfg: &'a CorpusConfig,
    scores: &'a [Score],
    works: WorksBySplit,
    seeds: Rng,
    train_violins: Vec<usize>,
    test_violins: Vec<usize>,
}

impl Draws<'_> {
    fn item(&self, i: usize) -> ItemDraw {
        let mut rng = self.seeds.fork(i as u64);
        let mut plan = plan_item(
            i,
            &mut rng,
            self.scores,
            &self.works,
            self.cfg.etude.target_s,
        );
        let score = score_of(&mut plan, self.scores, self.cfg);
        let pool = if plan.held_out_violin {
            &self.test_violins
        } else {
            &self.train_violins
        };
        let violin = rng.pick(pool).copied().unwrap_or(0);
        let renderer_rng = rng.fork(11);
        let item_seed = rng.next_u64();
        ItemDraw {
            plan,
            score,
            violin,
            rng: renderer_rng,
            item_seed,
        }
    }

    /// How many items make at least `cfg.minutes` of audio: each item's performance is drawn
    /// exactly as the build will draw it (cheap: no audio) until their lengths add up.
    fn count(&self) -> usize {
        let want_s = self.cfg.minutes * 60.0;
        let mut total_s = 0.0;
        let mut i = 0;
        while total_s < want_s && i < 1_000_000 {
            let d = self.item(i);
            total_s += crate::item::performed_length_s(&d.score, d.item_seed);
            i += 1;
        }
        i.max(1)
    }
}

/// The violin every item of one split is played by in a validation-violin or
/// training-violin corpus ([`CorpusConfig::validation_violin`],
/// [`CorpusConfig::training_violin`]).
struct RecastViolin {
    renderer: SoundFontRenderer,
    split: Split,
    name: String,
    info: ViolinInfo,
}

impl RecastViolin {
    /// The violin of `cfg`'s validation or training recast, if it asks for one.
    fn of(cfg: &CorpusConfig) -> Result<Option<Self>, CorpusError> {
        match (&cfg.validation_violin, &cfg.training_violin) {
            (Some(_), Some(_)) => Err(CorpusError::Config(
                "a validation violin and a training violin cannot be written into one corpus: \
                 build them into two folders"
                    .into(),
            )),
            (Some(path), None) => Self::load(path, Split::Val).map(Some),
            (None, Some(path)) => Self::load(path, Split::Train).map(Some),
            (None, None) => Ok(None),
        }
    }

    fn load(path: &Path, split: Split) -> Result<Self, CorpusError> {
        let (path, program) = split_program(path);
        let path = path.as_path();
        let is_patch = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("pat"));
        let is_webaudiofont = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("js"));
        let renderer = if path.is_dir() {
            SoundFontRenderer::from_sample_dir(path)?
        } else if is_webaudiofont {
            SoundFontRenderer::from_webaudiofont_file(path)?
        } else if is_patch {
            SoundFontRenderer::from_gus_patch_file(path)?
        } else {
            SoundFontRenderer::from_file(path)?.with_program(program)
        };
        let role = if split == Split::Val {
            "validation"
        } else {
            "training"
        };
        if !renderer.has_program(program) {
            return Err(CorpusError::Config(format!(
                "{}: has no GM program {program} to render the {role} items with",
                path.display()
            )));
        }
        let stem = path
            .file_stem()
            .map_or_else(|| "violin".into(), |s| s.to_string_lossy().to_string());
        let name = if program == 40 {
            format!("{role}:{stem}")
        } else {
            format!("{role}:{stem}-{program}")
        };
        let info = ViolinInfo {
            name: name.clone(),
            file: path.display().to_string(),
            license: "as its file states".into(),
            held_out: split != Split::Train,
        };
        Ok(Self {
            renderer,
            split,
            name,
            info,
        })
    }
}

/// An SF2 path with a GM program after a colon (`FluidR3_GM.sf2:41`, the viola) split into
/// the file and the program; any other path plays program 40 (violin).
fn split_program(path: &Path) -> (std::path::PathBuf, u8) {
    let text = path.to_string_lossy();
    if !path.exists() {
        if let Some((file, program)) = text.rsplit_once(':') {
            if let Ok(p) = program.parse::<u8>() {
                if p < 128 {
                    return (file.into(), p);
                }
            }
        }
    }
    (path.to_path_buf(), 40)
}

/// Builds a many-violin corpus into `root` (see [`crate::build::build_corpus`]).
pub fn build_many(
    root: &Path,
    cfg: &CorpusConfig,
    sf2_dir: &Path,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Manifest, CorpusError> {
    if cfg.augment {
        crate::room::check_encoders().map_err(|e| CorpusError::Io {
            path: root.to_path_buf(),
            reason: e.to_string(),
        })?;
    }
    let bank = ViolinBank::load(sf2_dir)?;
    let (scores, skipped) = match &cfg.repertoire {
        Some(dir) => crate::repertoire::read_dir(dir)?,
        None => (Vec::new(), Vec::new()),
    };
    let draws = Draws {
        cfg,
        scores: &scores,
        works: WorksBySplit::of(&scores),
        seeds: Rng::new(cfg.seed),
        train_violins: bank.indices(false),
        test_violins: bank.indices(true),
    };
    let count = draws.count();
    let recast = RecastViolin::of(cfg)?;
    let done = AtomicUsize::new(0);
    type Entry = (ManifestItem, Timeline, String, (usize, usize));
    let entries: Vec<Result<Option<Entry>, CorpusError>> = (0..count)
        .into_par_iter()
        .map(|i| {
            let ItemDraw {
                plan,
                score,
                violin,
                mut rng,
                item_seed,
            } = draws.item(i);
            if recast.as_ref().is_some_and(|v| plan.split != v.split) {
                progress(done.fetch_add(1, Ordering::Relaxed) + 1, count);
                return Ok(None);
            }
            let spec = bank
                .spec(violin)
                .ok_or_else(|| CorpusError::Config(format!("no violin source {violin}")))?;
            let (renderer, kind, name): (Box<dyn Renderer + '_>, RendererKind, &str) = match &recast
            {
                Some(v) => (
                    Box::new(v.renderer.clone()),
                    RendererKind::Soundfont,
                    &v.name,
                ),
                None => {
                    let renderer = bank
                        .renderer(violin, &mut rng)
                        .ok_or_else(|| CorpusError::Config(format!("no violin source {violin}")))?;
                    let kind = match spec.kind {
                        SourceKind::Builtin => RendererKind::Builtin,
                        SourceKind::Waveguide => RendererKind::Waveguide,
                        SourceKind::SoundFont { .. } => RendererKind::Soundfont,
                    };
                    (renderer, kind, spec.name)
                }
            };
            let item = make_score_item(&score, item_seed, renderer.as_ref(), kind, cfg.augment)?;
            let written = write_item(root, i, &item)?;
            let audio = crate::layout::item_audio(&written)
                .file_name()
                .map_or_else(|| "audio.wav".into(), |n| n.to_string_lossy().to_string());
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, count);
            let meter = item.time_signature.to_string();
            let chords = (
                item.double_stops.notes.len(),
                item.double_stops.pitches_dropped,
            );
            let entry = ManifestItem::of(i, &item, plan.split, plan.held_out, name, audio);
            Ok(Some((entry, item.timeline, meter, chords)))
        })
        .collect();
    let entries: Vec<Entry> = entries
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .flatten()
        .collect();
    let stats = CorpusStats::of(entries.iter().map(|(_, t, m, _)| (t, m.as_str())));
    let double_stops_played = entries.iter().map(|e| e.3 .0).sum();
    let chord_pitches_dropped = entries.iter().map(|e| e.3 .1).sum();
    let manifest = Manifest {
        version: MANIFEST_VERSION,
        seed: cfg.seed,
        renderer: "many".into(),
        items: entries.into_iter().map(|(e, _, _, _)| e).collect(),
        stats,
        violins: match &recast {
            Some(v) => vec![v.info.clone()],
            None => bank.infos(),
        },
        skipped_scores: skipped,
        double_stops_played,
        chord_pitches_dropped,
    };
    let json =
        serde_json::to_string_pretty(&manifest).map_err(|e| CorpusError::Config(e.to_string()))?;
    write_atomic(&root.join("manifest.json"), &json)?;
    Ok(manifest)
}
