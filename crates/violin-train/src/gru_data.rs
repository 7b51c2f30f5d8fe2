//! gru-baseline's training data ([`Dataset`] of [`gru_baseline::data::Sequence`]s) from disk. Two layouts are
//! read ([`load_dataset`] tells them apart):
//! * the synthetic **corpus** (`crates/corpus`): `manifest.json` + `items/NNNNN/{audio.wav,
//!   motion.json}`, with the manifest's splits ([`corpus`]);
//! * **URMP**: separated violin tracks `AuSep_K_vn_NAME.wav`, each with the OpenPose output
//!   of its player in `openpose_K_vn_NAME/` beside it, cleaned with
//!   `pose_preproc::preprocess_dir` ([`urmp`]).

pub mod corpus;
pub mod urmp;

use std::path::Path;

use gru_baseline::data::Dataset;
use gru_baseline::GruError;

use crate::error::Result;

/// Reads `root` as a corpus (it has `manifest.json`) or else as URMP, calling
/// `progress(done, total)` per recording.
pub fn load_dataset(root: &Path, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Dataset> {
    if !root.is_dir() {
        return Err(GruError::Data {
            path: root.to_path_buf(),
            reason:
                "not a directory; give a corpus (violin-skeleton corpus --out DIR) or a URMP folder"
                    .into(),
        }
        .into());
    }
    if root.join("manifest.json").is_file() {
        corpus::load_corpus(root, progress)
    } else {
        urmp::load_urmp(root, progress)
    }
}
