//! The stroke network: one temporal-convolution trunk, three per-frame heads.
//!
//! Input `(batch, frames, 130)` ([`super::stroke_input`]) → per-feature normalisation
//! (`norm.mean`, `norm.std`, from the training data) → [`net_core::nn::Tcn`] →
//! * `change`: the logit that the bow changes direction at the frame;
//! * `down`: the logit that the bow moves down (frog to tip) at the frame — trained, but it
//!   stays at chance on validation data (0.50): the audio does not tell the directions
//!   apart, so it is not used for inference ([`super::decode`]);
//! * `string`: four logits, the string being bowed (G, D, A, E).

use candle_core::{DType, Device, Module, Tensor, D};
use candle_nn::{Linear, VarBuilder};
use net_core::nn::{DropoutRng, Tcn, TcnConfig};
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

    /// Per-frame probabilities of one recording's input `(frames, features)`.
    pub fn frame_outputs(
        &self,
        input: &ndarray::Array2<f32>,
    ) -> Result<super::outputs::FrameOutputs> {
        let (frames, features) = input.dim();
        if frames == 0 {
            return Ok(super::outputs::FrameOutputs::default());
        }
        let x = Tensor::from_slice(
            input
                .as_slice()
                .ok_or_else(|| NetError::Config("input not contiguous".into()))?,
            (1, frames, features),
            &Device::Cpu,
        )?;
        let logits = self.forward_t(&x, false)?;
        let sig = |t: &Tensor| -> Result<Vec<f32>> {
            Ok(candle_nn::ops::sigmoid(t)?.squeeze(0)?.to_vec1::<f32>()?)
        };
        let strings = candle_nn::ops::softmax(&logits.string, D::Minus1)?
            .squeeze(0)?
            .to_vec2::<f32>()?
            .into_iter()
            .map(|v| [v[0], v[1], v[2], v[3]])
            .collect();
        Ok(super::outputs::FrameOutputs {
            change: sig(&logits.change)?,
            string: strings,
            down: sig(&logits.down)?,
        })
    }
}

/// The dtype of every variable.
pub const DTYPE: DType = DType::F32;
