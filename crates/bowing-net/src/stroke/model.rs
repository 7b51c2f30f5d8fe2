//! The stroke network: one temporal-convolution trunk, three per-frame heads.
//!
//! Input `(batch, frames, 130)` ([`super::stroke_input`]) → per-feature normalisation
//! (`norm.mean`, `norm.std`, from the training data) → [`net_core::nn::Tcn`] →
//! * `change`: the logit that the bow changes direction at the frame;
//! * `down`: the logit that the bow moves down (frog to tip) at the frame — trained, but it
//!   stays at chance on validation data (0.50): the audio does not tell the directions
//!   apart, so it is not used for inference ([`super::decode`]);
//! * `string`: four logits, the string being bowed (G, D, A, E).

use candle_core::{DType, Module, Tensor, D};
use candle_nn::{Linear, VarBuilder};
use net_core::nn::{linear_parts, linear_rows, softmax_in_place, DropoutRng, Tcn, TcnConfig};
use serde::{Deserialize, Serialize};

use crate::error::{NetError, Result};

/// The network's shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct StrokeConfig {
    /// Mel bands of the spectrogram it reads (its input has two more features).
    pub n_mels: usize,
    /// The trunk (its `in_features` is set from `n_mels`).
    pub trunk: TcnConfig,
}

impl Default for StrokeConfig {
    fn default() -> Self {
        let n_mels = 128;
        Self {
            n_mels,
            trunk: TcnConfig {
                in_features: super::input::input_features(n_mels),
                channels: 64,
                dilations: vec![1, 2, 4, 8, 16, 32, 1, 2, 4, 8, 16],
                dropout: 0.1,
            },
        }
    }
}

impl StrokeConfig {
    /// Checks that the shape is usable.
    pub fn validate(&self) -> Result<()> {
        if self.trunk.in_features != super::input::input_features(self.n_mels) {
            return Err(NetError::Config(format!(
                "the trunk reads {} features but {} mel bands give {}",
                self.trunk.in_features,
                self.n_mels,
                super::input::input_features(self.n_mels)
            )));
        }
        match self.trunk.problem() {
            Some(p) => Err(NetError::Config(p)),
            None => Ok(()),
        }
    }
}

/// The three heads' logits for every frame.
#[derive(Debug, Clone)]
pub struct StrokeLogits {
    /// `(batch, frames)`.
    pub change: Tensor,
    /// `(batch, frames)`.
    pub down: Tensor,
    /// `(batch, frames, 4)`.
    pub string: Tensor,
}

/// The stroke network (candle model style).
pub struct StrokeNet {
    cfg: StrokeConfig,
    mean: Tensor,
    std: Tensor,
    trunk: Tcn,
    heads: Linear,
}

impl std::fmt::Debug for StrokeNet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StrokeNet").field("cfg", &self.cfg).finish()
    }
}

/// Outputs of the shared head layer: change, down, four strings.
const HEAD_OUTPUTS: usize = 6;

impl StrokeNet {
    /// Builds the variables under `vb` (`norm.*`, `trunk.*`, `heads.*`); dropout draws from
    /// `rng`.
    pub fn new(cfg: &StrokeConfig, vb: VarBuilder, rng: DropoutRng) -> Result<Self> {
        cfg.validate()?;
        let features = cfg.trunk.in_features;
        let mean = vb.get_with_hints(features, "norm.mean", candle_nn::Init::Const(0.0))?;
        let std = vb.get_with_hints(features, "norm.std", candle_nn::Init::Const(1.0))?;
        let trunk = Tcn::new(&cfg.trunk, vb.pp("trunk"), rng)?;
        let heads = candle_nn::linear(cfg.trunk.channels, HEAD_OUTPUTS, vb.pp("heads"))?;
        Ok(Self {
            cfg: cfg.clone(),
            mean,
            std,
            trunk,
            heads,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &StrokeConfig {
        &self.cfg
    }

    /// `x`: `(batch, frames, features)` of [`super::stroke_input`]; `train` applies dropout.
    pub fn forward_t(&self, x: &Tensor, train: bool) -> Result<StrokeLogits> {
        let x = x.broadcast_sub(&self.mean)?.broadcast_div(&self.std)?;
        let h = self.trunk.forward_t(&x, train)?;
        let out = self.heads.forward(&h)?;
        Ok(StrokeLogits {
            change: out.narrow(D::Minus1, 0, 1)?.squeeze(D::Minus1)?,
            down: out.narrow(D::Minus1, 1, 1)?.squeeze(D::Minus1)?,
            string: out.narrow(D::Minus1, 2, 4)?,
        })
    }

    /// Per-frame probabilities of one recording's input `(frames, features)`: the
    /// function [`StrokeNet::forward_t`] computes without dropout, through the trunk's
    /// inference path ([`Tcn::forward_frames`]; values differ from `forward_t`'s in the
    /// last bits).
    pub fn frame_outputs(
        &self,
        input: &ndarray::Array2<f32>,
    ) -> Result<super::outputs::FrameOutputs> {
        let (frames, features) = input.dim();
        if frames == 0 {
            return Ok(super::outputs::FrameOutputs::default());
        }
        let (mean, std) = (self.mean.to_vec1::<f32>()?, self.std.to_vec1::<f32>()?);
        if features != mean.len() || features != std.len() {
            return Err(NetError::Input(format!(
                "{features} features per frame, the network reads {}",
                mean.len()
            )));
        }
        let mut x = input.clone();
        for mut row in x.rows_mut() {
            for ((v, m), s) in row.iter_mut().zip(&mean).zip(&std) {
                *v = (*v - m) / s;
            }
        }
        let h = self.trunk.forward_frames(x.view())?;
        let out = linear_rows(h.view(), &linear_parts(&self.heads)?);
        let sigmoid = |v: f32| 1.0 / (1.0 + (-v).exp());
        let softmax = |mut v: [f32; 4]| {
            softmax_in_place(&mut v);
            v
        };
        Ok(super::outputs::FrameOutputs {
            change: out.column(0).iter().map(|&v| sigmoid(v)).collect(),
            string: out
                .rows()
                .into_iter()
                .map(|r| softmax([r[2], r[3], r[4], r[5]]))
                .collect(),
            down: out.column(1).iter().map(|&v| sigmoid(v)).collect(),
        })
    }
}

/// The dtype of every variable.
pub const DTYPE: DType = DType::F32;
