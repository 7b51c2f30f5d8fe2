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
//! * [`data`]: the corpus's arousal proxy (default training data) and a DEAM loader;
//! * [`train`]: masked MSE, Adam, early stopping on validation Pearson r, checkpoints.
//!
//! It reuses bowing-net's `nn` building blocks (convolution, seeded dropout, Adam, weights
//! files).
//!
//! ```no_run
//! let est = emotion_net::ArousalEstimator::pretrained()?;
//! let mel = emotion_net::features::emotion_mel(&dsp_mel::load_audio("take1.wav")?)?;
//! let arousal = est.predict(mel.view())?; // one value per 0.5 s
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod batch_norm;
pub mod data;
mod error;
pub mod estimator;
pub mod evaluate;
pub mod features;
pub mod model;
pub mod train;

pub use error::{EmotionError, Result};
pub use estimator::ArousalEstimator;
pub use model::{Config, EmotionNet};
pub use train::{recalibrate_batch_norm, train, TrainConfig, TrainProgress, TrainReport};
