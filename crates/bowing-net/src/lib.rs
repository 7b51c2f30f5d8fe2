//! # bowing-net
//!
//! Where the bow changes, and which string it plays, from the 30 fps mel spectrogram, on
//! candle (CPU): the stroke network ([`stroke`], trained on the many-violin corpus), the
//! bow-change CNN of SPEC §4 (a 60-frame × 128-band mel window around a frame → the
//! probability of a change there), and [`BowingModel`], either one or their average (the
//! shipped default, [`BowingModel::pretrained`]).
//!
//! * [`model`]: the network ([`BowingNet`], candle model style: `Config`,
//!   `BowingNet::new(cfg, vb)`, `forward_t(&x, train)`) and its phase-tree evaluation that
//!   classifies every frame of a recording with shared convolutions;
//! * [`infer`]: stride-1 frame probabilities; [`decode`]: threshold + peak picking with a
//!   minimum spacing, and the splitting of merged runs of fast changes ([`RunSplit`]);
//! * with the `train` feature: `data` (labelled recordings in memory; `violin-train` reads
//!   them from the corpus or URMP), `train` (the training loop: Adam, class-balanced loss,
//!   early stopping, checkpoints and resume), `batch` (training sequences, frame targets and
//!   loss weights, augmentation) and `metrics` (P/R/F1 with a frame tolerance);
//! * [`BowChangeDetector`]: weights + normalisation + decoder in one safetensors file;
//!   [`BowChangeDetector::pretrained`] is the shipped default (see the README for how it was
//!   trained, and EXPERIMENTS.md for what was tried);
//! * layers (fast NHWC convolution, max pools with a correct backward, seeded dropout),
//!   weights files, Adam, schedules and checkpoints come from `net-core`.
//!
//! ```no_run
//! use bowing_net::{features::bowing_mel, BowChangeDetector};
//! let audio = dsp_mel::load_audio("take1.wav")?;
//! let mel = bowing_mel(&audio)?;                       // (frames, 128) dB at 30 fps
//! let detector = BowChangeDetector::pretrained()?;
//! let frames = detector.detect_frames(mel.view())?;   // bow-change frames
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#[cfg(feature = "train")]
pub mod batch;
mod choice;
#[cfg(feature = "train")]
pub mod data;
pub mod decode;
pub mod detector;
mod error;
pub mod features;
pub mod infer;
#[cfg(feature = "train")]
pub mod metrics;
pub mod model;
pub mod stroke;
#[cfg(feature = "train")]
pub mod train;

pub use choice::BowingModel;
pub use decode::{Decoder, RunSplit};
pub use detector::BowChangeDetector;
pub use error::{NetError, Result};
pub use model::{BowingNet, Config};
#[cfg(feature = "train")]
pub use train::{train, TrainConfig, TrainProgress, TrainReport};
