//! # violin-train
//!
//! Everything that trains or measures violin-skeleton's networks and is not needed to run
//! them (a tool crate, `publish = false`):
//!
//! * [`bowing_data`], [`beat_data`], [`emotion_data`], [`gru_data`]: the networks' labelled data read from
//!   disk — the synthetic corpus (`violin-skeleton corpus`), URMP with OpenPose skeletons
//!   (labels through `pose-preproc`) and DEAM — into the in-memory types the nets' `train`
//!   feature trains on;
//! * [`item_score`]: a corpus item's score as a MIDI file would give it;
//! * [`feature_cache`]: an item's 30 fps mel spectrogram computed once and kept beside its
//!   audio, for repeated training runs;
//! * [`evaluate`]: the engine of `violin-skeleton evaluate`, every SPEC §10 measure of the
//!   whole pipeline on a labelled folder;
//! * examples: the research and fitting scripts (`cargo run -p violin-train --example …`),
//!   their options read by [`example_args`].
//!
//! The training loops themselves live in each network crate behind its `train` feature
//! (`bowing_net::train`, `emotion_net::train`, `gru_baseline::train`); this crate turns that
//! feature on.
//!
//! ```no_run
//! use std::path::Path;
//! let data = violin_train::bowing_data::load_dataset(Path::new("corpus"), &|_, _| {})?;
//! let cfg = bowing_net::TrainConfig::default();
//! let out = Path::new("bowing.safetensors");
//! let report = bowing_net::train(&data, &cfg, out, false, &mut |_| {})?;
//! println!("best validation F1 {:.3}", report.best_val_f1);
//! # Ok::<(), violin_train::TrainError>(())
//! ```

pub mod beat_data;
pub mod bowing_data;
pub mod emotion_data;
mod error;
pub mod evaluate;
pub mod example_args;
pub mod feature_cache;
pub mod gru_data;
pub mod item_score;
pub mod stroke_directions;

pub use error::{Result, TrainError};
