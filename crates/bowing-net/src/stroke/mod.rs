//! The stroke network: bow changes and the string being bowed, per frame, from one
//! temporal-convolution trunk, and the decoding of its outputs into bow changes and
//! strings.
//!
//! * [`stroke_input`]: the gain-normalised per-frame input made from the 30 fps mel;
//! * [`StrokeNet`] (candle model style: [`StrokeConfig`], `StrokeNet::new(cfg, vb, rng)`,
//!   `forward_t`);
//! * [`decode`]: played stretches (level and tonality), bow changes inside them, the
//!   string of a span;
//! * [`direction`]: stroke directions from the down-bow output, the bars and the bowing
//!   rules, decoded over all strokes at once ([`StrokeAnalysis::directions`]);
//! * [`StrokeDetector`]: weights + normalisation + decoder in one safetensors file.

pub mod decode;
mod detector;
pub mod direction;
mod direction_choice;
mod input;
mod long_runs;
#[cfg(feature = "train")]
pub mod metrics;
mod model;
mod outputs;
#[cfg(feature = "train")]
pub mod timbre;
#[cfg(feature = "train")]
pub mod train;

pub use detector::{
    average_changes, played, stroke_shapes, StrokeAnalysis, StrokeDetector, STROKE_FORMAT_NAME,
    STROKE_FORMAT_VERSION,
};
pub use input::{
    input_features, reference_level_db, stroke_input, tonal_prominence_db, FLOOR_DB,
    REFERENCE_FLOOR_DB,
};
pub use model::{StrokeConfig, StrokeLogits, StrokeNet, DTYPE as STROKE_DTYPE};
pub use outputs::FrameOutputs;
