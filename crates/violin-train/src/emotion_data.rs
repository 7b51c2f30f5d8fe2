//! emotion-net's arousal-labelled recordings ([`ArousalTrack`], [`ArousalSplits`]) from the synthetic corpus's arousal proxy (default) or DEAM.
//!
//! **Corpus layout**: `DIR/manifest.json` + `DIR/items/NNNNN/{audio.wav, performance.json,
//! arousal.csv}`; splits from the manifest. The target is the corpus's arousal proxy,
//! recomputed from the item's notes and dynamics (`performance.json`) with
//! [`performance::arousal_proxy_of_spans`], so corpora written before the proxy's change
//! train on the current definition; [`CorpusTarget::File`] reads `arousal.csv` (`time_s,
//! arousal` at 2 Hz from 0 s) as written instead.
//!
//! **DEAM layout**: `DIR/annotations/annotations averaged per song/dynamic (per second
//! annotations)/arousal.csv` in DEAM's wide format (`song_id,sample_15000ms,sample_15500ms,…`,
//! one row per song, trailing cells may be empty or `NaN` when a song is shorter) and the
//! audio `DIR/MEMD_audio/{song_id}.mp3` — or `{song_id}.wav`, which is also accepted so
//! that fixtures and converted copies need no MP3 encoder. A song's annotation at
//! `sample_Tms` is the target of mel frame `T / 500`. Songs are sorted by id and split like the
//! corpus (index ending in 3 → test, 7 → validation).

use std::path::{Path, PathBuf};

use corpus::manifest::Split;
use emotion_net::data::{ArousalSplits, ArousalTrack};
use emotion_net::features::emotion_mel_of_file;
use emotion_net::EmotionError;
use rayon::prelude::*;

use crate::bowing_data::read_manifest;
use crate::error::Result;

/// The DEAM arousal file below a DEAM root.
pub const DEAM_AROUSAL_CSV: &str =
    "annotations/annotations averaged per song/dynamic (per second annotations)/arousal.csv";

fn push(splits: &mut ArousalSplits, split: Split, t: ArousalTrack) {
    match split {
        Split::Train => splits.train.push(t),
        Split::Val => splits.val.push(t),
        Split::Test => splits.test.push(t),
    }
}

/// Where a corpus item's arousal targets come from.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CorpusTarget {
    /// The corpus's current arousal proxy, recomputed from `performance.json`.
    #[default]
    Proxy,
    /// `arousal.csv` as the corpus wrote it.
    File,
}

/// Loads a data folder by its layout: `manifest.json` → corpus (the recomputed proxy),
/// else DEAM.
pub fn load_dataset(dir: &Path, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<ArousalSplits> {
    if dir.join("manifest.json").is_file() {
        load_corpus_with(dir, CorpusTarget::Proxy, progress)
    } else {
        load_deam(dir, progress)
    }
}

fn cut(mut track: ArousalTrack) -> ArousalTrack {
    let available = track.mel_db.nrows().saturating_sub(track.first_frame);
    track.arousal.truncate(available);
    track
}

/// Reads a corpus `arousal.csv` (`time_s,arousal`, 2 Hz from 0 s).
pub fn read_corpus_arousal(path: &Path) -> Result<Vec<f32>> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| EmotionError::data(path, format!("cannot read ({e})")))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let mut cells = line.split(',');
        let (Some(t), Some(a)) = (cells.next(), cells.next()) else {
            return Err(EmotionError::data(
                path,
                format!("line {}: expected time_s,arousal", i + 1),
            )
            .into());
        };
        let t: f64 = t
            .trim()
            .parse()
            .map_err(|_| EmotionError::data(path, format!("line {}: bad time \"{t}\"", i + 1)))?;
        let a: f32 = a.trim().parse().map_err(|_| {
            EmotionError::data(path, format!("line {}: bad arousal \"{a}\"", i + 1))
        })?;
        if !a.is_finite() || (t - 0.5 * out.len() as f64).abs() > 1e-3 {
            return Err(EmotionError::data(
                path,
                format!(
                    "line {}: expected a finite value at {} s",
                    i + 1,
                    0.5 * out.len() as f64
                ),
            )
            .into());
        }
        out.push(a);
    }
    if out.is_empty() {
        return Err(EmotionError::data(path, "no arousal values").into());
    }
    Ok(out)
}

/// The corpus's arousal proxy (2 Hz from 0 s) of an item, from its `performance.json`
/// (notes and per-note dynamics).
pub fn corpus_proxy(item_dir: &Path) -> Result<Vec<f32>> {
    let path = item_dir.join("performance.json");
    let perf = performance::Performance::read_json(&path)
        .map_err(|e| EmotionError::data(&path, format!("cannot read the performance ({e})")))?;
    let dynamics = perf.dynamics().ok_or_else(|| {
        EmotionError::data(
            &path,
            "the performance has no per-note dynamics: rebuild the corpus or use arousal.csv",
        )
    })?;
    let spans: Vec<(f64, f64, f32)> = perf
        .notes()
        .iter()
        .zip(dynamics)
        .map(|(n, &d)| (n.onset_s, n.offset_s, d))
        .collect();
    Ok(performance::arousal_proxy_of_spans(
        &spans,
        perf.duration_s(),
    ))
}

/// Loads the corpus's audio and arousal proxy by the manifest's splits.
pub fn load_corpus(dir: &Path, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<ArousalSplits> {
    load_corpus_with(dir, CorpusTarget::Proxy, progress)
}

/// Loads the corpus's audio and the `target` arousal by the manifest's splits.
pub fn load_corpus_with(
    dir: &Path,
    target: CorpusTarget,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<ArousalSplits> {
    let manifest = read_manifest(dir)?;
    let total = manifest.items.len();
    if total == 0 {
        return Err(
            EmotionError::data(dir.join("manifest.json"), "the corpus has no items").into(),
        );
    }
    let done = std::sync::atomic::AtomicUsize::new(0);
    let loaded: Vec<Result<(Split, ArousalTrack)>> = manifest
        .items
        .par_iter()
        .map(|item| {
            let d = dir.join(&item.dir);
            let group = item.renderer.name();
            let track = cut(ArousalTrack {
                name: item.dir.clone(),
                group: group.into(),
                mel_db: emotion_mel_of_file(&corpus::layout::item_audio(&d))?,
                first_frame: 0,
                arousal: match target {
                    CorpusTarget::Proxy => corpus_proxy(&d)?,
                    CorpusTarget::File => read_corpus_arousal(&d.join("arousal.csv"))?,
                },
            });
            progress(
                done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                total,
            );
            Ok((item.split, track))
        })
        .collect();
    let mut out = ArousalSplits::default();
    for r in loaded {
        let (s, t) = r?;
        push(&mut out, s, t);
    }
    Ok(out)
}

/// One DEAM song's annotation row.
#[derive(Debug, Clone, PartialEq)]
pub struct DeamRow {
    /// `song_id`.
    pub song_id: String,
    /// Time of the first value in milliseconds.
    pub first_ms: u32,
    /// Values every 500 ms up to the first empty or `NaN` cell.
    pub arousal: Vec<f32>,
}

/// Parses DEAM's wide `arousal.csv`.
pub fn read_deam_arousal(path: &Path) -> Result<Vec<DeamRow>> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        EmotionError::data(
            path,
            format!("cannot read the DEAM arousal annotations ({e}); is this a DEAM folder?"),
        )
    })?;
    let mut lines = text.lines();
    let header = lines
        .next()
        .ok_or_else(|| EmotionError::data(path, "empty file"))?;
    let mut times = Vec::new();
    for (k, cell) in header.split(',').enumerate().skip(1) {
        let cell = cell.trim().trim_matches('"');
        let ms: u32 = cell
            .strip_prefix("sample_")
            .and_then(|c| c.strip_suffix("ms"))
            .and_then(|c| c.parse().ok())
            .ok_or_else(|| {
                EmotionError::data(
                    path,
                    format!("header cell {} \"{cell}\" is not sample_<N>ms", k + 1),
                )
            })?;
        times.push(ms);
    }
    let Some(&first_ms) = times.first() else {
        return Err(EmotionError::data(path, "the header has no sample_<N>ms column").into());
    };
    if times
        .iter()
        .enumerate()
        .any(|(k, &t)| t != first_ms + 500 * k as u32)
        || first_ms % 500 != 0
    {
        return Err(
            EmotionError::data(path, "columns must be 500 ms apart on a 500 ms grid").into(),
        );
    }
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let mut cells = line.split(',');
        let song_id = cells
            .next()
            .unwrap_or_default()
            .trim()
            .trim_matches('"')
            .to_string();
        if song_id.is_empty() {
            return Err(EmotionError::data(path, format!("line {}: no song_id", i + 2)).into());
        }
        let mut arousal = Vec::new();
        for cell in cells {
            let cell = cell.trim();
            if cell.is_empty() || cell.eq_ignore_ascii_case("nan") {
                break;
            }
            let v: f32 = cell.parse().map_err(|_| {
                EmotionError::data(path, format!("line {}: \"{cell}\" is not a number", i + 2))
            })?;
            if !v.is_finite() {
                break;
            }
            arousal.push(v);
        }
        rows.push(DeamRow {
            song_id,
            first_ms,
            arousal,
        });
    }
    Ok(rows)
}

/// The audio file of a DEAM song: `MEMD_audio/{id}.mp3`, else `{id}.wav`.
pub fn deam_audio_path(dir: &Path, song_id: &str) -> Result<PathBuf> {
    let audio = dir.join("MEMD_audio");
    for ext in ["mp3", "wav"] {
        let p = audio.join(format!("{song_id}.{ext}"));
        if p.is_file() {
            return Ok(p);
        }
    }
    Err(EmotionError::data(
        audio.join(format!("{song_id}.mp3")),
        "audio of an annotated song is missing (.mp3 or .wav)",
    )
    .into())
}

/// Loads a DEAM folder (module docs).
pub fn load_deam(dir: &Path, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<ArousalSplits> {
    let csv = dir.join(DEAM_AROUSAL_CSV);
    if !csv.is_file() {
        return Err(EmotionError::data(
            dir,
            format!(
                "neither a corpus (manifest.json) nor a DEAM folder ({DEAM_AROUSAL_CSV} not found)"
            ),
        )
        .into());
    }
    let mut rows: Vec<DeamRow> = read_deam_arousal(&csv)?
        .into_iter()
        .filter(|r| !r.arousal.is_empty())
        .collect();
    if rows.is_empty() {
        return Err(EmotionError::data(&csv, "no song has annotations").into());
    }
    rows.sort_by(|a, b| a.song_id.cmp(&b.song_id));
    let splits = Split::assign(rows.len());
    let done = std::sync::atomic::AtomicUsize::new(0);
    let loaded: Vec<Result<ArousalTrack>> = rows
        .par_iter()
        .map(|row| {
            let mel_db = emotion_mel_of_file(&deam_audio_path(dir, &row.song_id)?)?;
            progress(
                done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                rows.len(),
            );
            Ok(cut(ArousalTrack {
                name: row.song_id.clone(),
                group: "deam".into(),
                mel_db,
                first_frame: (row.first_ms / 500) as usize,
                arousal: row.arousal.clone(),
            }))
        })
        .collect();
    let mut out = ArousalSplits::default();
    for (t, s) in loaded.into_iter().zip(splits) {
        push(&mut out, s, t?);
    }
    Ok(out)
}
