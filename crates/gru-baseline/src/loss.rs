//! The training loss: MSE, or SPEC §8's per-coordinate weighted MSE
//! `L = (1/N) Σ wⱼ (yⱼ − ŷⱼ)²` with heavier weights on the bowing arm.

use candle_core::Tensor;
use ndarray::ArrayView2;
use serde::{Deserialize, Serialize};
use skeleton::{Joint, JOINT_COUNT};

use crate::error::{GruError, Result};

/// The default extra weight of the right (bowing) arm in the weighted loss.
pub const DEFAULT_RIGHT_ARM_WEIGHT: f32 = 3.0;

/// A per-coordinate weighted MSE over `(frames, 20)` joints (x, y of each joint of
/// `skeleton::Joint::ALL`); all weights 1 is the plain MSE. `N` counts the frames × 20
/// coordinates averaged over (not the weights), as in SPEC §8.
///
/// ```
/// use gru_baseline::Loss;
/// let loss = Loss::right_arm_weighted(3.0);
/// assert!(loss.is_weighted());
/// // right wrist x (joint 4) weighs 3, nose x weighs 1
/// assert_eq!((loss.weights[8], loss.weights[0]), (3.0, 1.0));
/// assert!(!Loss::mse().is_weighted());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Loss {
    /// One weight per output coordinate: `2·joint + {0: x, 1: y}`.
    pub weights: Vec<f32>,
}

impl Default for Loss {
    /// The weighted loss with [`DEFAULT_RIGHT_ARM_WEIGHT`].
    fn default() -> Self {
        Self::right_arm_weighted(DEFAULT_RIGHT_ARM_WEIGHT)
    }
}

impl Loss {
    /// Plain MSE (every weight 1).
    pub fn mse() -> Self {
        Self {
            weights: vec![1.0; 2 * JOINT_COUNT],
        }
    }

    /// Weight `factor` on the right shoulder, elbow and wrist (x and y), 1 elsewhere.
    pub fn right_arm_weighted(factor: f32) -> Self {
        let mut weights = vec![1.0; 2 * JOINT_COUNT];
        for j in [Joint::RShoulder, Joint::RElbow, Joint::RWrist] {
            weights[2 * j.index()] = factor;
            weights[2 * j.index() + 1] = factor;
        }
        Self { weights }
    }

    /// Whether any weight differs from 1.
    pub fn is_weighted(&self) -> bool {
        self.weights.iter().any(|&w| w != 1.0)
    }

    /// Checks there are 20 finite, non-negative weights, not all zero.
    pub fn validate(&self) -> Result<()> {
        if self.weights.len() != 2 * JOINT_COUNT {
            return Err(GruError::Config(format!(
                "the loss needs {} weights (x, y per joint), got {}",
                2 * JOINT_COUNT,
                self.weights.len()
            )));
        }
        if self.weights.iter().any(|w| !(w.is_finite() && *w >= 0.0))
            || self.weights.iter().all(|&w| w == 0.0)
        {
            return Err(GruError::Config(format!(
                "loss weights must be finite, >= 0 and not all 0, got {:?}",
                self.weights
            )));
        }
        Ok(())
    }

    /// The loss of predictions `pred` against `target`, both `(B, T, 20)`; `mask` `(B, T)`
    /// (1 = counts, 0 = padding) restricts `N` to the frames that count. A scalar tensor with
    /// gradients.
    pub fn compute(&self, pred: &Tensor, target: &Tensor, mask: Option<&Tensor>) -> Result<Tensor> {
        self.validate()?;
        if pred.dims() != target.dims() || pred.rank() != 3 || pred.dim(2)? != self.weights.len() {
            return Err(GruError::Shape {
                what: "loss inputs".into(),
                expected: format!("two equal (batch, frames, {})", self.weights.len()),
                got: format!("{:?} and {:?}", pred.dims(), target.dims()),
            });
        }
        let w = Tensor::from_slice(&self.weights, (1, 1, self.weights.len()), pred.device())?;
        let sq = (pred - target)?.sqr()?.broadcast_mul(&w)?;
        let coords = self.weights.len() as f64;
        match mask {
            None => Ok(sq.mean_all()?),
            Some(m) => {
                let (b, t, _) = pred.dims3()?;
                if m.dims() != [b, t] {
                    return Err(GruError::Shape {
                        what: "loss mask".into(),
                        expected: format!("({b}, {t})"),
                        got: format!("{:?}", m.dims()),
                    });
                }
                let count = m.sum_all()?.to_scalar::<f32>()?;
                if count <= 0.0 {
                    return Err(GruError::Empty("loss mask (no frame counts)".into()));
                }
                let total = sq.broadcast_mul(&m.unsqueeze(2)?)?.sum_all()?;
                Ok((total / (f64::from(count) * coords))?)
            }
        }
    }

    /// The same loss on plain arrays `(frames, 20)`, in f64 (for evaluation).
    pub fn compute_array(&self, pred: ArrayView2<f32>, target: ArrayView2<f32>) -> Result<f64> {
        self.validate()?;
        if pred.dim() != target.dim() || pred.ncols() != self.weights.len() {
            return Err(GruError::Shape {
                what: "loss inputs".into(),
                expected: format!("two equal (frames, {})", self.weights.len()),
                got: format!("{:?} and {:?}", pred.dim(), target.dim()),
            });
        }
        if pred.is_empty() {
            return Err(GruError::Empty("loss inputs".into()));
        }
        let mut sum = 0.0f64;
        for (p, t) in pred.rows().into_iter().zip(target.rows()) {
            for ((a, b), w) in p.iter().zip(t.iter()).zip(&self.weights) {
                sum += f64::from(*w) * f64::from(a - b).powi(2);
            }
        }
        Ok(sum / pred.len() as f64)
    }
}
