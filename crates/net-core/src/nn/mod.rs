//! Layers shared by the networks on candle's CPU backend: a fast channels-last
//! convolution (optionally fused with its ReLU), max pools with a correct backward (one
//! alignment, or both time alignments of the phase tree at once), seeded dropout, a
//! weighted cross-entropy, and the temporal convolution trunk ([`Tcn`]) of the frame-level
//! networks. (Weights files, Adam and checkpoints are beside this module in
//! net-core.)

mod conv;
#[cfg(target_arch = "x86_64")]
mod conv_direct;
mod conv_pool;
mod dropout;
mod geometry;
mod pool;
mod storage;
mod tcn;

pub use conv::{conv2d_nhwc, conv2d_relu_nhwc, Conv2dNhwc};
pub use conv_pool::conv2d_relu_pool_phases_nhwc;
pub use dropout::{DropoutRng, SeededDropout};
pub use pool::{
    max_pool2x2_nhwc, pool_phases_nhwc, MaxPool2x2, MaxPool2x2Backward, PoolPhases,
    PoolPhasesBackward,
};
pub use tcn::{linear_parts, linear_rows, softmax_in_place, Tcn, TcnConfig};

/// Cross-entropy of two-class `logits` `(n, 2)` against `targets` (0/1, `n`) with
/// per-example `weights` `(n)`: `Σ wᵢ·CEᵢ / Σ wᵢ` (0 when all weights are 0).
pub fn weighted_cross_entropy(
    logits: &candle_core::Tensor,
    targets: &candle_core::Tensor,
    weights: &candle_core::Tensor,
) -> candle_core::Result<candle_core::Tensor> {
    let log_p = candle_nn::ops::log_softmax(logits, candle_core::D::Minus1)?;
    let picked = log_p.gather(&targets.unsqueeze(1)?, 1)?.squeeze(1)?;
    let total = weights.sum_all()?.to_scalar::<f32>()?;
    let scale = if total > 0.0 {
        -1.0 / f64::from(total)
    } else {
        0.0
    };
    (picked * weights)?.sum_all()? * scale
}
