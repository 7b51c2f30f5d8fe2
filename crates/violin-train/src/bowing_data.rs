//! bowing-net's labelled recordings ([`Recording`], [`Splits`]) loaded, from the synthetic corpus (exact bow
//! changes) or a URMP-style folder (labels from the skeleton, SPEC §3).
//!
//! **Corpus layout** (`violin-skeleton corpus`): `DIR/manifest.json` and
//! `DIR/items/NNNNN/{audio.wav, bowchanges.txt, notes.tsv}`; the manifest gives each item's
//! split.
//!
//! **URMP layout**: any folder tree holding separated violin tracks `AuSep_K_vn_NAME.wav`
//! (URMP's naming) each with an OpenPose directory of that player beside it, named
//! `openpose_K_vn_NAME/` (one `*_keypoints.json` per video frame at 30 fps). Labels come from
//! `pose_preproc::preprocess_dir` (SPEC §3). Tracks are sorted by path and split like the
//! corpus (index ending in 3 → test, 7 → validation).

use std::path::{Path, PathBuf};

use bowing_net::data::{Recording, Splits};
use bowing_net::features::{bowing_mel_of_file, frame_of};
use bowing_net::NetError;
use corpus::manifest::{Manifest, Split};
use fingering::ViolinString;
use performance::{BowDirection, BowStroke};
use pose_preproc::PreprocConfig;
use rayon::prelude::*;

use crate::error::Result;

fn push(splits: &mut Splits, split: Split, r: Recording) {
    match split {
        Split::Train => splits.train.push(r),
        Split::Val => splits.val.push(r),
        Split::Test => splits.test.push(r),
    }
}

/// Loads a data folder, telling the layout by its content: `manifest.json` → corpus,
/// otherwise URMP. `progress(done, total)` is called as recordings are loaded.
pub fn load_dataset(dir: &Path, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Splits> {
    if dir.join("manifest.json").is_file() {
        load_corpus(dir, progress)
    } else {
        load_urmp(dir, &PreprocConfig::default(), progress)
    }
}

/// Reads a corpus manifest.
pub fn read_manifest(dir: &Path) -> Result<Manifest> {
    let path = dir.join("manifest.json");
    let text = std::fs::read_to_string(&path).map_err(|e| {
        NetError::data(&path, format!("cannot read the corpus manifest ({e}); make a corpus with `violin-skeleton corpus`"))
    })?;
    Ok(serde_json::from_str(&text)
        .map_err(|e| NetError::data(&path, format!("not a corpus manifest ({e})")))?)
}

/// Times in seconds, one per line (blank lines skipped).
pub fn read_times(path: &Path) -> Result<Vec<f64>> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| NetError::data(path, format!("cannot read ({e})")))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let v: f64 = line.parse().map_err(|_| {
            NetError::data(
                path,
                format!("line {}: \"{line}\" is not a time in seconds", i + 1),
            )
        })?;
        if !v.is_finite() || v < 0.0 {
            return Err(NetError::data(
                path,
                format!(
                    "line {}: time {v} is not a finite, non-negative number",
                    i + 1
                ),
            )
            .into());
        }
        out.push(v);
    }
    Ok(out)
}

/// Note onsets (s) from a corpus `notes.tsv` (`onset_s  offset_s  midi`, with a header).
pub fn read_note_onsets(path: &Path) -> Result<Vec<f64>> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| NetError::data(path, format!("cannot read ({e})")))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        let Some(first) = line.split('\t').next().filter(|s| !s.trim().is_empty()) else {
            continue;
        };
        let v: f64 = first.trim().parse().map_err(|_| {
            NetError::data(
                path,
                format!("line {}: \"{first}\" is not an onset in seconds", i + 1),
            )
        })?;
        out.push(v);
    }
    Ok(out)
}

/// Strokes from a corpus `strokes.tsv` (`start_s  end_s  direction  string`, with a header).
pub fn read_strokes(path: &Path) -> Result<Vec<BowStroke>> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| NetError::data(path, format!("cannot read ({e})")))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let bad = |what: &str| NetError::data(path, format!("line {}: {what}", i + 1));
        let cols: Vec<&str> = line.split('\t').map(str::trim).collect();
        let [start, end, direction, string, ..] = cols.as_slice() else {
            return Err(bad("expected start_s, end_s, direction and string").into());
        };
        let time = |s: &str| s.parse::<f64>().ok().filter(|v| v.is_finite() && *v >= 0.0);
        let (Some(start_s), Some(end_s)) = (time(start), time(end)) else {
            return Err(bad("start_s and end_s must be non-negative seconds").into());
        };
        let direction = match *direction {
            "down" => BowDirection::Down,
            "up" => BowDirection::Up,
            other => return Err(bad(&format!("direction \"{other}\" is not down or up")).into()),
        };
        let string = string.parse::<u8>().ok().and_then(|n| {
            ViolinString::ALL
                .get(usize::from(n).wrapping_sub(1))
                .copied()
        });
        out.push(BowStroke {
            start_s,
            end_s,
            direction,
            string,
        });
    }
    Ok(out)
}

/// The string (1–4; 0 for none) of the sounding note at every one of `frames` frames, from a
/// corpus `notes.tsv` whose fourth column is the string; all 0 when the file has no string
/// column.
pub fn read_note_strings(path: &Path, frames: usize) -> Result<Vec<u8>> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| NetError::data(path, format!("cannot read ({e})")))?;
    let mut out = vec![0u8; frames];
    let mut lines = text.lines();
    let has_string = lines
        .next()
        .is_some_and(|h| h.split('\t').nth(3).map(str::trim) == Some("string"));
    if !has_string {
        return Ok(out);
    }
    for line in lines {
        let cols: Vec<&str> = line.split('\t').map(str::trim).collect();
        let (Some(on), Some(off), Some(string)) = (
            cols.first().and_then(|v| v.parse::<f64>().ok()),
            cols.get(1).and_then(|v| v.parse::<f64>().ok()),
            cols.get(3).and_then(|v| v.parse::<u8>().ok()),
        ) else {
            continue;
        };
        if !(1..=4).contains(&string) || !on.is_finite() || !off.is_finite() {
            continue;
        }
        let from = frame_of(on).min(frames);
        let to = frame_of(off).min(frames);
        for v in &mut out[from..to.max(from)] {
            *v = string;
        }
    }
    Ok(out)
}

fn frames_of(times: &[f64], frames: usize) -> Vec<usize> {
    let mut out: Vec<usize> = times
        .iter()
        .map(|&t| frame_of(t))
        .filter(|&f| f < frames)
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// Loads one corpus item folder.
pub fn load_corpus_item(dir: &Path, name: &str, group: &str) -> Result<Recording> {
    let mel_db = crate::feature_cache::cached_mel30(dir, &corpus::layout::item_audio(dir))?;
    let frames = mel_db.nrows();
    let change_s = read_times(&dir.join("bowchanges.txt"))?;
    let onset_s = read_note_onsets(&dir.join("notes.tsv"))?;
    let slurred_s: Vec<f64> = onset_s
        .iter()
        .copied()
        .filter(|o| !change_s.iter().any(|c| (c - o).abs() < 1e-3))
        .collect();
    let strokes_path = dir.join("strokes.tsv");
    let strokes = if strokes_path.is_file() {
        read_strokes(&strokes_path)?
    } else {
        Vec::new()
    };
    let strings = read_note_strings(&dir.join("notes.tsv"), frames)?;
    Ok(Recording {
        name: name.to_string(),
        group: group.to_string(),
        changes: frames_of(&change_s, frames),
        onsets: frames_of(&onset_s, frames),
        slurred: frames_of(&slurred_s, frames),
        mel_db,
        strokes,
        strings,
    })
}

/// Loads every item of a corpus, by the manifest's splits.
pub fn load_corpus(dir: &Path, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Splits> {
    let manifest = read_manifest(dir)?;
    if manifest.items.is_empty() {
        return Err(NetError::data(dir.join("manifest.json"), "the corpus has no items").into());
    }
    let total = manifest.items.len();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let loaded: Vec<Result<(Split, Recording)>> = manifest
        .items
        .par_iter()
        .map(|item| {
            let group = item.renderer.name();
            let r = load_corpus_item(&dir.join(&item.dir), &item.dir, group)?;
            progress(
                done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                total,
            );
            Ok((item.split, r))
        })
        .collect();
    let mut splits = Splits::default();
    for r in loaded {
        let (split, rec) = r?;
        push(&mut splits, split, rec);
    }
    Ok(splits)
}

/// A URMP violin track and its OpenPose directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UrmpTrack {
    /// `AuSep_K_vn_NAME.wav`.
    pub audio: PathBuf,
    /// `openpose_K_vn_NAME/`.
    pub openpose: PathBuf,
}

/// Finds every `AuSep_*_vn_*.wav` below `dir` with its `openpose_*` directory, sorted.
/// A violin track without a pose directory is an error naming the directory expected.
pub fn find_urmp_tracks(dir: &Path) -> Result<Vec<UrmpTrack>> {
    let mut stack = vec![dir.to_path_buf()];
    let mut out = Vec::new();
    while let Some(d) = stack.pop() {
        let entries =
            std::fs::read_dir(&d).map_err(|e| NetError::data(&d, format!("cannot list ({e})")))?;
        for entry in entries {
            let path = entry.map_err(|e| NetError::data(&d, e))?.path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
                continue;
            };
            let Some(stem) = name
                .strip_prefix("AuSep_")
                .and_then(|s| s.strip_suffix(".wav"))
            else {
                continue;
            };
            if stem.split('_').nth(1) != Some("vn") {
                continue;
            }
            let openpose = d.join(format!("openpose_{stem}"));
            if !openpose.is_dir() {
                return Err(NetError::data(
                    &path,
                    format!(
                        "no OpenPose directory for this track: expected {}",
                        openpose.display()
                    ),
                )
                .into());
            }
            out.push(UrmpTrack {
                audio: path,
                openpose,
            });
        }
    }
    out.sort_by(|a, b| a.audio.cmp(&b.audio));
    if out.is_empty() {
        return Err(NetError::data(
            dir,
            "neither a corpus (manifest.json) nor a URMP folder (AuSep_K_vn_NAME.wav + openpose_K_vn_NAME/)",
        ).into());
    }
    Ok(out)
}

/// Loads one URMP track: mel of the audio, bow changes from the skeleton (both at 30 fps,
/// cut to the shorter of the two).
pub fn load_urmp_track(track: &UrmpTrack, cfg: &PreprocConfig) -> Result<Recording> {
    let mel = bowing_mel_of_file(&track.audio)?;
    let pose = pose_preproc::preprocess_dir(&track.openpose, cfg)?;
    let frames = mel.nrows().min(pose.motion.len());
    let mel_db = mel.slice(ndarray::s![..frames, ..]).to_owned();
    let changes: Vec<usize> = pose
        .bow_change_frames
        .iter()
        .copied()
        .filter(|&f| f < frames)
        .collect();
    let name = track
        .audio
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("track")
        .to_string();
    Ok(Recording {
        name,
        group: "urmp".into(),
        mel_db,
        changes,
        onsets: Vec::new(),
        slurred: Vec::new(),
        strokes: Vec::new(),
        strings: Vec::new(),
    })
}

/// Loads a URMP-style folder (module docs).
pub fn load_urmp(
    dir: &Path,
    cfg: &PreprocConfig,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Splits> {
    let tracks = find_urmp_tracks(dir)?;
    let splits = Split::assign(tracks.len());
    let done = std::sync::atomic::AtomicUsize::new(0);
    let loaded: Vec<Result<Recording>> = tracks
        .par_iter()
        .map(|t| {
            let r = load_urmp_track(t, cfg);
            progress(
                done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                tracks.len(),
            );
            r
        })
        .collect();
    let mut out = Splits::default();
    for (r, split) in loaded.into_iter().zip(splits) {
        push(&mut out, split, r?);
    }
    Ok(out)
}

/// Moves the training items played by `violin` (a source of the corpus's manifest) into
/// the validation set, so that the network never trains on that violin and validation sees
/// how a new violin fares. Returns how many were moved; a violin no item uses is an error.
pub fn move_violin_to_validation(corpus: &Path, violin: &str, data: &mut Splits) -> Result<usize> {
    let manifest = read_manifest(corpus)?;
    let played_by: std::collections::BTreeSet<&str> = manifest
        .items
        .iter()
        .filter(|i| i.violin == violin)
        .map(|i| i.dir.as_str())
        .collect();
    if played_by.is_empty() {
        return Err(NetError::data(
            corpus.join("manifest.json"),
            format!("no item is played by violin {violin}"),
        )
        .into());
    }
    let (moved, kept): (Vec<Recording>, Vec<Recording>) = std::mem::take(&mut data.train)
        .into_iter()
        .partition(|r| played_by.contains(r.name.as_str()));
    data.train = kept;
    let n = moved.len();
    data.val.extend(moved);
    Ok(n)
}

/// Adds the validation items of a validation-violin corpus (`violin-skeleton corpus …
/// --validation-violin V`: the same items played by a violin training never hears) to
/// `data`'s validation set, each named by its folder's absolute path so that its audio can
/// be found from the name. Returns how many were added.
pub fn add_validation_violin(dir: &Path, data: &mut Splits) -> Result<usize> {
    let root = std::fs::canonicalize(dir)
        .map_err(|e| NetError::data(dir, format!("cannot open the corpus folder ({e})")))?;
    let extra = load_dataset(&root, &|_, _| {})?;
    Ok(add_named(&root, extra.val, &mut data.val))
}

/// Adds the training items of a training-violin corpus (`violin-skeleton corpus …
/// --training-violin V`: the training items played by one more violin) to `data`'s training
/// set, named as in [`add_validation_violin`]. Returns how many were added; a corpus with no
/// training item is refused.
pub fn add_training_violin(dir: &Path, data: &mut Splits) -> Result<usize> {
    let root = std::fs::canonicalize(dir)
        .map_err(|e| NetError::data(dir, format!("cannot open the corpus folder ({e})")))?;
    let extra = load_dataset(&root, &|_, _| {})?;
    if extra.train.is_empty() {
        return Err(NetError::data(&root, "has no training item to add").into());
    }
    Ok(add_named(&root, extra.train, &mut data.train))
}

/// Appends `items` to `to`, each renamed by its folder's absolute path under `root`.
fn add_named(root: &Path, items: Vec<Recording>, to: &mut Vec<Recording>) -> usize {
    let n = items.len();
    for mut r in items {
        r.name = root.join(&r.name).display().to_string();
        to.push(r);
    }
    n
}
