//! URMP with OpenPose skeletons (what the original trained on, SPEC §9).
//!
//! Layout (the same as `bowing-net`'s, so one folder trains both): any folder tree holding
//! URMP's separated violin tracks `AuSep_K_vn_NAME.wav`, each with the OpenPose output of
//! that player's video (one `*_keypoints.json` per frame, 30 fps) beside it in
//! `openpose_K_vn_NAME/`. Each skeleton is cleaned by `pose_preproc::preprocess_dir`
//! (performer selection, gap filling, median smoothing) **without** its re-centring, so
//! joints stay in image pixels. Tracks are sorted by path and split 80/10/10 like the corpus
//! (`corpus::manifest::Split::assign`: index ending in 3 → test, 7 → validation).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use corpus::manifest::Split;
use pose_preproc::{preprocess_dir, PreprocConfig};
use rayon::prelude::*;

use gru_baseline::data::{DataLayout, Dataset, Sequence};
use gru_baseline::GruError;

use crate::error::Result;

/// One violin track of URMP and its OpenPose directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UrmpTrack {
    /// `AuSep_K_vn_NAME.wav`.
    pub audio: PathBuf,
    /// `openpose_K_vn_NAME/`.
    pub openpose: PathBuf,
}

/// The stem `K_vn_NAME` of a separated violin track `AuSep_K_vn_NAME.wav`, if it is one.
///
/// ```
/// use violin_train::gru_data::urmp::violin_track_stem;
/// assert_eq!(violin_track_stem("AuSep_2_vn_03_Dance_vn_vn.wav"), Some("2_vn_03_Dance_vn_vn"));
/// assert_eq!(violin_track_stem("AuSep_1_vc_03_Dance.wav"), None);
/// ```
pub fn violin_track_stem(file_name: &str) -> Option<&str> {
    let stem = file_name.strip_prefix("AuSep_")?.strip_suffix(".wav")?;
    stem.split('_')
        .nth(1)
        .is_some_and(|inst| inst == "vn")
        .then_some(stem)
}

/// Finds every `AuSep_*_vn_*.wav` below `root` (recursively) with its `openpose_*`
/// directory, sorted by path. A violin track without one is an error naming the directory
/// expected.
pub fn find_tracks(root: &Path) -> Result<Vec<UrmpTrack>> {
    let mut stack = vec![root.to_path_buf()];
    let mut out = Vec::new();
    while let Some(dir) = stack.pop() {
        let entries = std::fs::read_dir(&dir).map_err(|e| GruError::Data {
            path: dir.clone(),
            reason: format!("cannot list the folder ({e})"),
        })?;
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let Some(stem) = path
                .file_name()
                .and_then(|n| n.to_str())
                .and_then(violin_track_stem)
            else {
                continue;
            };
            let openpose = dir.join(format!("openpose_{stem}"));
            if !openpose.is_dir() {
                return Err(GruError::Data {
                    path: path.clone(),
                    reason: format!(
                        "no OpenPose directory for this violin track: expected {}",
                        openpose.display()
                    ),
                }
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
        return Err(GruError::Data {
            path: root.to_path_buf(),
            reason: "neither a corpus (manifest.json) nor a URMP folder (AuSep_K_vn_NAME.wav + openpose_K_vn_NAME/)".into(),
        }.into());
    }
    Ok(out)
}

/// Loads one URMP track: the separated violin audio and its cleaned skeleton.
pub fn load_track(track: &UrmpTrack) -> Result<Sequence> {
    let audio = dsp_mel::load_audio(&track.audio)?;
    let cfg = PreprocConfig {
        center: false,
        ..PreprocConfig::default()
    };
    let pose = preprocess_dir(&track.openpose, &cfg)?;
    Ok(Sequence::from_audio_and_motion(
        track.audio.display().to_string(),
        &audio,
        &pose.motion,
    )?)
}

/// Loads every violin track under `root` (in parallel) and splits them.
pub fn load_urmp(root: &Path, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Dataset> {
    let tracks = find_tracks(root)?;
    let total = tracks.len();
    let done = AtomicUsize::new(0);
    let loaded: Vec<Result<Sequence>> = tracks
        .par_iter()
        .map(|t| {
            let seq = load_track(t)?;
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            Ok(seq)
        })
        .collect();
    let mut data = Dataset {
        layout: DataLayout::Urmp,
        train: Vec::new(),
        val: Vec::new(),
        test: Vec::new(),
    };
    for (seq, split) in loaded.into_iter().zip(Split::assign(total)) {
        let seq = seq?;
        match split {
            Split::Train => data.train.push(seq),
            Split::Val => data.val.push(seq),
            Split::Test => data.test.push(seq),
        }
    }
    Ok(data)
}
