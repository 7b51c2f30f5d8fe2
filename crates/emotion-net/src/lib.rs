//! # emotion-net
//!
//! The arousal CRNN of SPEC §7 on candle (CPU): 20 steps (10 s) of a 2 fps × 64-band mel
//! spectrogram → one arousal value per step in [-1, 1] (DEAM convention).
//!
//! * [`model`]: the network ([`EmotionNet`]: `Config`, `EmotionNet::new(cfg, vb)`,
//!   `forward_t(&x, train)`);
//! * [`estimator`]: [`ArousalEstimator`] — weights + normalisation in one safetensors
//!   file, whole-recording inference with overlap-averaged sliding windows;
//!   [`ArousalEstimator::pretrained`] is the shipped default (see the README);
//! * with the `train` feature: `data` (arousal-labelled tracks in memory; `violin-train`
//!   reads them from the corpus or DEAM), `train` (masked MSE, Adam, early stopping on
//!   validation Pearson r, checkpoints) and `evaluate` (Pearson r and RMSE).
//!
//! Layers (convolution, seeded dropout), Adam and weights files come from `net-core`.
//!
//! ```no_run
//! let est = emotion_net::ArousalEstimator::pretrained()?;
//! let mel = emotion_net::features::emotion_mel(&dsp_mel::load_audio("take1.wav")?)?;
//! let arousal = est.predict(mel.view())?; // one value per 0.5 s
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod batch_norm;
#[cfg(feature = "train")]
pub mod data;
mod error;
pub mod estimator;
#[cfg(feature = "train")]
pub mod evaluate;
pub mod features;
pub mod model;
#[cfg(feature = "train")]
pub mod train;
#[cfg(feature = "train")]
mod windows;

pub use error::{EmotionError, Result};
pub use estimator::ArousalEstimator;
pub use model::{Config, EmotionNet};
#[cfg(feature = "train")]
pub use train::{recalibrate_batch_norm, train, TrainConfig, TrainProgress, TrainReport};
