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
use crate::manifest::{Manifest, ManifestItem, MANIFEST_VERSION};
use crate::schedule::{plan_item, HeldOut, ItemPlan, Music, WorksBySplit};
use crate::score::Score;
use crate::stats::CorpusStats;
use crate::violins::{SourceKind, ViolinBank};
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

/// How many items make about `cfg.minutes` of audio: items are planned and a timing drawn
/// for each (cheap: no audio) until their lengths add up.
fn item_count(cfg: &CorpusConfig, scores: &[Score], works: &WorksBySplit, seeds: &Rng) -> usize {
    let want_s = cfg.minutes * 60.0;
    let mut total_s = 0.0;
    let mut i = 0;
    while total_s < want_s && i < 1_000_000 {
        let mut rng = seeds.fork(i as u64);
        let mut plan = plan_item(i, &mut rng, scores, works, cfg.etude.target_s);
        let score = score_of(&mut plan, scores, cfg);
        let played = crate::perform::perform(&score, rng.next_u64(), (40.0, 200.0));
        total_s += played.timeline.duration_s;
        i += 1;
    }
    i.max(1)
}

/// Builds a many-violin corpus into `root` (see [`crate::build::build_corpus`]).
pub fn build_many(
    root: &Path,
    cfg: &CorpusConfig,
    sf2_dir: &Path,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Manifest, CorpusError> {
    let bank = ViolinBank::load(sf2_dir)?;
    let (scores, skipped) = match &cfg.repertoire {
        Some(dir) => crate::repertoire::read_dir(dir)?,
        None => (Vec::new(), Vec::new()),
    };
    let works = WorksBySplit::of(&scores);
    let seeds = Rng::new(cfg.seed);
    let count = item_count(cfg, &scores, &works, &seeds);
    let train_violins = bank.indices(false);
    let test_violins = bank.indices(true);
    let done = AtomicUsize::new(0);
    type Entry = (ManifestItem, Timeline, String, usize);
    let entries: Vec<Result<Entry, CorpusError>> = (0..count)
        .into_par_iter()
        .map(|i| {
            let mut rng = seeds.fork(i as u64);
            let mut plan = plan_item(i, &mut rng, &scores, &works, cfg.etude.target_s);
            let score = score_of(&mut plan, &scores, cfg);
            let pool = if plan.held_out_violin {
                &test_violins
            } else {
                &train_violins
            };
            let violin = rng.pick(pool).copied().unwrap_or(0);
            let spec = bank
                .spec(violin)
                .ok_or_else(|| CorpusError::Config(format!("no violin source {violin}")))?;
            let renderer = bank
                .renderer(violin, &mut rng.fork(11))
                .ok_or_else(|| CorpusError::Config(format!("no violin source {violin}")))?;
            let kind = match spec.kind {
                SourceKind::Builtin => RendererKind::Builtin,
                SourceKind::Waveguide => RendererKind::Waveguide,
                SourceKind::SoundFont { .. } => RendererKind::Soundfont,
            };
            let item =
                make_score_item(&score, rng.next_u64(), renderer.as_ref(), kind, cfg.augment)?;
            let written = write_item(root, i, &item)?;
            let audio = crate::layout::item_audio(&written)
                .file_name()
                .map_or_else(|| "audio.wav".into(), |n| n.to_string_lossy().to_string());
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, count);
            let meter = item.time_signature.to_string();
            let double_stops = score.notes.iter().filter(|n| !n.lower.is_empty()).count();
            let entry = ManifestItem::of(i, &item, plan.split, plan.held_out, spec.name, audio);
            Ok((entry, item.timeline, meter, double_stops))
        })
        .collect();
    let entries = entries.into_iter().collect::<Result<Vec<_>, _>>()?;
    let stats = CorpusStats::of(entries.iter().map(|(_, t, m, _)| (t, m.as_str())));
    let double_stops_reduced = entries.iter().map(|e| e.3).sum();
    let manifest = Manifest {
        version: MANIFEST_VERSION,
        seed: cfg.seed,
        renderer: "many".into(),
        items: entries.into_iter().map(|(e, _, _, _)| e).collect(),
        stats,
        violins: bank.infos(),
        skipped_scores: skipped,
        double_stops_reduced,
    };
    let json =
        serde_json::to_string_pretty(&manifest).map_err(|e| CorpusError::Config(e.to_string()))?;
    write_atomic(&root.join("manifest.json"), &json)?;
    Ok(manifest)
}
