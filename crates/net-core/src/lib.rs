//! # net-core
//!
//! What violin-skeleton's candle networks (bowing-net, emotion-net, gru-baseline) share for
//! inference, training and storing weights, so each network crate keeps only what is its own:
//!
//! * [`rng`]: the seeded, stable random generator every seeded draw of the workspace uses
//!   (the synthetic corpus too, whose output must not change with a dependency);
//! * [`file`](mod@file): safetensors weights files with string metadata — the network's format name
//!   and version, its configuration as JSON — decoded with checks (format, version, tensor
//!   shapes, truncation, non-finite values) whose errors name the file and what to do;
//! * [`frames`]: the spectrogram input checks and windowing every network runs;
//! * [`nn`]: layers on candle's CPU backend (fast NHWC convolution, max pools with a correct
//!   backward, seeded dropout, weighted cross-entropy);
//! * [`vars`]: a `VarMap`'s variables by name (shapes, copies, trainable subsets, loading,
//!   seeded Glorot initialisation);
//! * [`Adam`] with checkpointable moments, [`LrSchedule`] (exponential or warm-up + cosine);
//! * [`checkpoint`]: [`TrainState`] (early stopping on a validation metric, losses) and
//!   checkpoint files for `--resume`;
//! * [`band_statistics`] for per-band input normalisation;
//! * [`gradcheck`]: finite-difference gradient checks for tests.
//!
//! ```
//! use net_core::{LrSchedule, TrainState};
//! let schedule = LrSchedule::WarmupCosine { warmup_fraction: 0.05, final_fraction: 0.02 };
//! let mut state = TrainState::new("config", -1.0);
//! for epoch in 0..3 {
//!     let lr = schedule.rate(2e-3, epoch * 100, 100, 3);
//!     assert!(lr > 0.0 && lr <= 2e-3);
//!     state.end_epoch(epoch, 0.1, 0.5 + epoch as f64 * 0.1);
//! }
//! assert_eq!(state.best_epoch, 2);
//! ```

mod adam;
pub mod checkpoint;
mod error;
pub mod file;
pub mod frames;
pub mod gradcheck;
pub mod nn;
pub mod rng;
mod schedule;
mod stats;
pub mod vars;

pub use adam::{Adam, AdamConfig};
pub use checkpoint::{
    checkpoint_path, load_checkpoint, resume_from_checkpoint, save_checkpoint, TrainState,
};
pub use error::{Result, StoreError};
pub use file::{TensorFile, KEY_FORMAT, KEY_VERSION};
pub use schedule::LrSchedule;
pub use stats::{band_statistics, set_band_statistics};
