//! # beat-net
//!
//! A learned beat and downbeat activation for solo violin (issue 20), in the style of
//! madmom's `RNNDownBeatProcessor` and Beat This!: the 30 fps × 128 mel dB spectrogram the
//! bowing network also reads → per-frame probabilities of *no beat*, *beat* and *downbeat*.
//! Decoding those into beats, downbeats and a metre is `beat_track::bar_pointer`'s job (the
//! facade composes the two).
//!
//! * [`features`]: gain-normalised mel frames plus spectral flux and loudness;
//! * [`model`]: the network ([`BeatNet`]: `Config`, `BeatNet::new(cfg, vb)`, `forward_t`), a
//!   dilated temporal convolution trunk from `net-core` and a 3-class head;
//! * [`BeatActivation`]: weights + normalisation in one safetensors file;
//!   [`BeatActivation::pretrained`] is the shipped default (see the README for its training);
//! * with the `train` feature: `data` (recordings in memory; `violin-train` reads the
//!   corpus), `batch` (random crops with tempo augmentation) and `train` (the loop).
//!
//! ```no_run
//! let net = beat_net::BeatActivation::pretrained()?;
//! let mel = ndarray::Array2::<f32>::from_elem((900, 128), -50.0); // 30 s at 30 fps
//! let act = net.activations(mel.view())?;
//! println!("strongest beat activation {:?}", act.any_beat().iter().cloned().fold(0.0, f32::max));
//! # Ok::<(), beat_net::BeatNetError>(())
//! ```

pub mod activation;
#[cfg(feature = "train")]
pub mod batch;
#[cfg(feature = "train")]
pub mod data;
mod error;
pub mod features;
pub mod model;
#[cfg(feature = "train")]
pub mod train;

pub use activation::{Activations, BeatActivation};
pub use error::{BeatNetError, Result};
pub use model::{BeatNet, Config};
#[cfg(feature = "train")]
pub use train::{train, TrainConfig, TrainProgress, TrainReport};
