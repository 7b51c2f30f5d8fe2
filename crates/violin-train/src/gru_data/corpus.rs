//! The synthetic corpus: `DIR/manifest.json` and `DIR/items/NNNNN/{audio.wav, motion.json}`
//! (see `crates/corpus/README.md`); the manifest's splits are kept.

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use corpus::manifest::{Manifest, Split};
use rayon::prelude::*;
use skeleton::formats::MotionFormat;
use skeleton::Motion;

use gru_baseline::data::{DataLayout, Dataset, Sequence};
use gru_baseline::GruError;

use crate::error::Result;

/// Reads the corpus manifest at `root/manifest.json`.
pub fn read_manifest(root: &Path) -> Result<Manifest> {
    let path = root.join("manifest.json");
    let text = std::fs::read_to_string(&path).map_err(|e| GruError::Data {
        path: path.clone(),
        reason: format!("cannot read the corpus manifest ({e})"),
    })?;
    Ok(serde_json::from_str(&text).map_err(|e| GruError::Data {
        path,
        reason: format!("not a corpus manifest ({e}); rebuild with `violin-skeleton corpus`"),
    })?)
}

/// Loads one corpus item folder: `audio.wav` + `motion.json`.
pub fn load_item(dir: &Path) -> Result<Sequence> {
    let audio_path = corpus::layout::item_audio(dir);
    let audio = dsp_mel::load_audio(&audio_path)?;
    let motion = Motion::read(dir.join("motion.json"), MotionFormat::Json)?;
    Ok(Sequence::from_audio_and_motion(
        dir.display().to_string(),
        &audio,
        &motion,
    )?)
}

/// Loads every item of the corpus at `root` (in parallel), split as its manifest says.
pub fn load_corpus(root: &Path, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Dataset> {
    let manifest = read_manifest(root)?;
    if manifest.items.is_empty() {
        return Err(GruError::Data {
            path: root.join("manifest.json"),
            reason: "the corpus has no items; rebuild it with more --minutes".into(),
        }
        .into());
    }
    let total = manifest.items.len();
    let done = AtomicUsize::new(0);
    let loaded: Vec<Result<(Split, Sequence)>> = manifest
        .items
        .par_iter()
        .map(|item| {
            let seq = load_item(&root.join(&item.dir))?;
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            Ok((item.split, seq))
        })
        .collect();
    let mut data = Dataset {
        layout: DataLayout::Corpus,
        train: Vec::new(),
        val: Vec::new(),
        test: Vec::new(),
    };
    for entry in loaded {
        let (split, seq) = entry?;
        match split {
            Split::Train => data.train.push(seq),
            Split::Val => data.val.push(seq),
            Split::Test => data.test.push(seq),
        }
    }
    if data.train.is_empty() {
        return Err(GruError::Data {
            path: root.join("manifest.json"),
            reason: "no training items in the manifest".into(),
        }
        .into());
    }
    Ok(data)
}
