//! # gru-baseline
//!
//! Method 1 of violin-skeleton (SPEC §8), the baseline the product's Method 2 must beat:
//! one recurrent network maps each 30 fps, 128-band mel frame straight to the ten joints.
//!
//! * **Network** ([`GruBaseline`], [`Config`]): GRU 256 → dropout .3 → GRU 512 → dropout .3 →
//!   GRU 256 → dropout .3 → dense 20, on candle, with an optional output delay
//!   ([`Config::lookahead_frames`]). Each GRU layer is a [`FusedGru`]: the input projection of
//!   all time steps is one matmul and the recurrence one custom op with a hand-written
//!   backward pass, numerically equal to candle's `rnn::GRU` (tests).
//! * **Normalisation** ([`norm`]): mel bands standardised with training statistics; joints
//!   centred on each video's trunk and divided by its mean torso length, then each coordinate
//!   standardised; outputs de-normalised into the training targets' image space (Method 2's
//!   1280×720 camera for the shipped weights), so the two methods' motions overlay.
//! * **Loss** ([`Loss`]): MSE, or the per-coordinate weighted MSE with 3× weight on the right
//!   shoulder, elbow and wrist (default).
//! * **Training** (feature `train`): `data` (sequences in memory; `violin-train` reads them
//!   from the synthetic corpus or URMP + OpenPose), `train` (truncated BPTT over windows of
//!   parallel streams that carry their state, Adam with clipping from `net-core`,
//!   validation, best-weights saving, checkpoints, `--resume`) and `eval` (validation
//!   scores).
//! * **Inference** ([`GruBaseline::generate`]): audio → [`skeleton::Motion`] at 30 fps. A
//!   recording is cut into chunks that run side by side as one batch, each with a warm-up
//!   ([`Chunking`], [`chunking`]), the batch rows split over the cores;
//!   [`GruBaseline::predict_normalized_exact`] is the sequential run.
//!   [`GruBaseline::pretrained`] embeds the default weights.
//!
//! ```
//! let net = gru_baseline::GruBaseline::pretrained()?;
//! let tone: Vec<f32> = (0..22_050).map(|i| 0.2 * (i as f32 * 0.08).sin()).collect();
//! let motion = net.generate(&dsp_mel::Audio::new(tone, 22_050)?)?;
//! assert_eq!(motion.len(), 31);
//! assert_eq!(motion.image_size(), Some((1280, 720)));
//! # Ok::<(), gru_baseline::GruError>(())
//! ```

pub mod chunking;
mod config;
#[cfg(feature = "train")]
pub mod data;
mod error;
#[cfg(feature = "train")]
pub mod eval;
pub mod features;
mod fused_gru;
mod gates;
mod infer;
mod loss;
mod model;
pub mod norm;
mod packed;
mod recurrence;
#[cfg(feature = "train")]
pub mod train;
mod weights;

pub use chunking::{Chunk, Chunking, DEFAULT_WARMUP_FRAMES};
pub use config::{Config, DEFAULT_LOOKAHEAD_FRAMES, MAX_LOOKAHEAD_FRAMES};
pub use error::{GruError, Result};
pub use fused_gru::FusedGru;
pub use infer::CHUNK_FRAMES;
pub use loss::{Loss, DEFAULT_RIGHT_ARM_WEIGHT};
pub use model::{GruBaseline, GruState};
pub use norm::{MelStats, TargetSpace, VideoNorm};
pub use weights::{expected_shapes, StorageDtype, TrainingRecord, FORMAT_NAME, FORMAT_VERSION};
