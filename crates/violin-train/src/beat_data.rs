//! beat-net's labelled recordings read from the corpus (`violin-skeleton corpus`): each
//! item's cached 30 fps mel ([`crate::feature_cache`]) with `beats.txt` and `downbeats.txt`
//! (seconds in the first column), by the manifest's split. Only `train` and `val` items are
//! read; the test sets are never seen by training or tuning.

use std::path::Path;

use beat_net::data::{Recording, Splits};
use corpus::manifest::Split;
use rayon::prelude::*;

use crate::bowing_data::read_manifest;
use crate::error::{Result, TrainError};

/// Times in seconds from the first column of a whitespace-separated file (blank lines
/// skipped; a malformed or negative time is an error naming the line).
pub fn read_first_column(path: &Path) -> Result<Vec<f64>> {
    let bad = |reason: String| TrainError::Dataset {
        path: path.to_path_buf(),
        reason,
    };
    let text = std::fs::read_to_string(path).map_err(|e| bad(format!("cannot read ({e})")))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let Some(first) = line.split_whitespace().next() else {
            continue;
        };
        match first.parse::<f64>() {
            Ok(v) if v.is_finite() && v >= 0.0 => out.push(v),
            _ => {
                return Err(bad(format!(
                    "line {}: \"{first}\" is not a time in seconds",
                    i + 1
                )))
            }
        }
    }
    Ok(out)
}

/// Beats per bar and tempo (bpm) at the notated beat from a corpus item's `labels.json`,
/// when it has them. The tempo is the one **played**: the median of `tempo_bpm_per_beat`
/// (the statistic the trackers report), or the nominal `tempo_bpm` when the labels have no
/// per-beat tempi. The nominal tempo is the performance model's starting point, which its
/// tempo curve moves: in 96 of corpus-hook's 1,290 items the played median is more than 8 %
/// away from it, so a tracker with every beat right would be scored wrong against it.
pub fn notated_meter(item_dir: &Path) -> (Option<u8>, Option<f64>) {
    let labels: Option<serde_json::Value> = std::fs::read_to_string(item_dir.join("labels.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let get = |key: &str| labels.as_ref().and_then(|l| l.get(key)?.as_f64());
    let mut played: Vec<f64> = labels
        .as_ref()
        .and_then(|l| l.get("tempo_bpm_per_beat")?.as_array().cloned())
        .unwrap_or_default()
        .iter()
        .filter_map(serde_json::Value::as_f64)
        .filter(|t| t.is_finite() && *t > 0.0)
        .collect();
    played.sort_by(f64::total_cmp);
    let played_median = played.get(played.len() / 2).copied();
    (
        get("beats_per_bar")
            .filter(|b| (1.0..=255.0).contains(b))
            .map(|b| b as u8),
        played_median.or_else(|| get("tempo_bpm").filter(|t| *t > 0.0)),
    )
}

/// One corpus item folder as a [`Recording`].
pub fn load_beat_item(dir: &Path, name: &str) -> Result<Recording> {
    let mel = crate::feature_cache::cached_mel30(dir, &corpus::layout::item_audio(dir))?;
    let beats_s = read_first_column(&dir.join("beats.txt"))?;
    let downbeats_s = read_first_column(&dir.join("downbeats.txt"))?;
    Recording::from_mel(name.to_string(), mel.view(), beats_s, downbeats_s).map_err(|e| {
        TrainError::Dataset {
            path: dir.to_path_buf(),
            reason: e.to_string(),
        }
    })
}

/// The items of the corpus at `dir` whose split is one of `splits`, in manifest order, each
/// with its split; `progress(done, total)` as they load.
fn load_beat_items(
    dir: &Path,
    splits: &[Split],
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<(Split, Recording)>> {
    let manifest = read_manifest(dir)?;
    let wanted: Vec<_> = manifest
        .items
        .iter()
        .filter(|it| splits.contains(&it.split))
        .collect();
    let total = wanted.len();
    let done = std::sync::atomic::AtomicUsize::new(0);
    wanted
        .par_iter()
        .map(|item| {
            let rec = load_beat_item(&dir.join(&item.dir), &item.dir)?;
            progress(
                done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                total,
            );
            Ok((item.split, rec))
        })
        .collect()
}

/// The train and validation items of the corpus at `dir`; `progress(done, total)` as they
/// load.
pub fn load_beat_corpus(dir: &Path, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Splits> {
    let mut splits = Splits::default();
    for (split, rec) in load_beat_items(dir, &[Split::Train, Split::Val], progress)? {
        match split {
            Split::Train => splits.train.push(rec),
            _ => splits.val.push(rec),
        }
    }
    if splits.train.is_empty() || splits.val.is_empty() {
        return Err(TrainError::Dataset {
            path: dir.to_path_buf(),
            reason: "the corpus needs train and val items to train the beat network".into(),
        });
    }
    Ok(splits)
}

/// Only the `train` items of the corpus at `dir`: more training music from a second corpus
/// built with another seed. Works go to splits by a stable hash of their name
/// (`corpus::schedule::work_split`), so these are training works; its validation and test
/// items are not read.
pub fn load_beat_train_split(
    dir: &Path,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<Recording>> {
    let train: Vec<Recording> = load_beat_items(dir, &[Split::Train], progress)?
        .into_iter()
        .map(|(_, rec)| rec)
        .collect();
    if train.is_empty() {
        return Err(TrainError::Dataset {
            path: dir.to_path_buf(),
            reason: "the corpus has no train items".into(),
        });
    }
    Ok(train)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_column_is_read_and_bad_lines_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("beats.txt");
        std::fs::write(&p, "0.5 1\n\n1.25\t2\n").unwrap();
        assert_eq!(read_first_column(&p).unwrap(), vec![0.5, 1.25]);
        std::fs::write(&p, "0.5\nabc\n").unwrap();
        let e = read_first_column(&p).unwrap_err().to_string();
        assert!(e.contains("line 2"), "{e}");
        assert!(read_first_column(&dir.path().join("missing.txt")).is_err());
        assert_eq!(notated_meter(dir.path()), (None, None));
        std::fs::write(
            dir.path().join("labels.json"),
            r#"{"beats_per_bar": 3, "tempo_bpm": 90.5}"#,
        )
        .unwrap();
        assert_eq!(notated_meter(dir.path()), (Some(3), Some(90.5)));
        // The played tempo (median of the per-beat tempi) wins over the nominal one.
        std::fs::write(
            dir.path().join("labels.json"),
            r#"{"beats_per_bar": 3, "tempo_bpm": 90.5, "tempo_bpm_per_beat": [80, 84, 82, -1]}"#,
        )
        .unwrap();
        assert_eq!(notated_meter(dir.path()), (Some(3), Some(82.0)));
    }
}
