//! The beat/downbeat network in candle's model style.
//!
//! `(batch, frames, n_mels + 2)` input frames ([`crate::features`]) → per-band
//! standardisation (constants stored with the weights) → a dilated temporal convolution
//! trunk ([`net_core::nn::Tcn`], by default 32 channels, dilations 1…64 twice: a receptive
//! field of 509 frames, 17 s) → ReLU → `Linear(channels, 3)`: logits of *no beat*, *beat*
//! and *downbeat* per frame (softmax, as madmom's `RNNDownBeatProcessor`).

use candle_core::{DType, Device, Module, Tensor};
use candle_nn::{Init, Linear, VarBuilder, VarMap};
use ndarray::{Array2, ArrayView2};
use net_core::nn::{linear_parts, linear_rows, DropoutRng, Tcn, TcnConfig};
use serde::{Deserialize, Serialize};

use crate::error::{BeatNetError, Result};
use crate::features::{input_features, N_MELS};

/// Output classes per frame: no beat, beat (not a downbeat), downbeat.
pub const CLASSES: usize = 3;
/// The model's variables are all f32.
pub const DTYPE: DType = DType::F32;

/// The network's shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Config {
    /// Mel bands of the input (the trunk's input is `n_mels + 2` features).
    pub n_mels: usize,
    /// The temporal convolution trunk.
    pub tcn: TcnConfig,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            n_mels: N_MELS,
            tcn: TcnConfig {
                in_features: input_features(N_MELS),
                channels: 32,
                dilations: vec![1, 2, 4, 8, 16, 32, 64, 1, 2, 4, 8, 16, 32, 64],
                dropout: 0.1,
            },
        }
    }
}

impl Config {
    /// Checks that the shape is usable.
    pub fn validate(&self) -> Result<()> {
        if self.tcn.in_features != input_features(self.n_mels) {
            return Err(BeatNetError::Config(format!(
                "the trunk takes {} features per frame, the input has {} ({} mel bands + 2)",
                self.tcn.in_features,
                input_features(self.n_mels),
                self.n_mels
            )));
        }
        match self.tcn.problem() {
            Some(p) => Err(BeatNetError::Config(p)),
            None => Ok(()),
        }
    }
}

/// The beat/downbeat network (module docs).
pub struct BeatNet {
    cfg: Config,
    norm_mean: Tensor,
    norm_std: Tensor,
    tcn: Tcn,
    head: Linear,
    rng: DropoutRng,
}

impl std::fmt::Debug for BeatNet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BeatNet").field("cfg", &self.cfg).finish()
    }
}

impl BeatNet {
    /// Builds the network from `vb` (names: `norm.{mean,std}`, `tcn.*` as
    /// [`net_core::nn::Tcn`], `head.{weight,bias}`).
    ///
    /// ```
    /// use candle_core::{DType, Device, Tensor};
    /// let varmap = candle_nn::VarMap::new();
    /// let vb = candle_nn::VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu);
    /// let net = beat_net::BeatNet::new(&Default::default(), vb)?;
    /// let x = Tensor::zeros((2, 40, 130), DType::F32, &Device::Cpu)?;
    /// assert_eq!(net.forward_t(&x, false)?.dims(), &[2, 40, 3]);
    /// # Ok::<(), beat_net::BeatNetError>(())
    /// ```
    pub fn new(cfg: &Config, vb: VarBuilder) -> Result<Self> {
        cfg.validate()?;
        let f = cfg.tcn.in_features;
        let norm = vb.pp("norm");
        let norm_mean = norm.get_with_hints(f, "mean", Init::Const(0.0))?;
        let norm_std = norm.get_with_hints(f, "std", Init::Const(1.0))?;
        let rng = DropoutRng::new(0);
        let tcn = Tcn::new(&cfg.tcn, vb.pp("tcn"), rng.clone())?;
        let head = candle_nn::linear(cfg.tcn.channels, CLASSES, vb.pp("head"))?;
        Ok(Self {
            cfg: cfg.clone(),
            norm_mean,
            norm_std,
            tcn,
            head,
            rng,
        })
    }

    /// A network of `cfg` in a fresh `VarMap` with seeded Glorot-uniform weights (the
    /// residual blocks' output layers and the head scaled by 0.1, so that the 14 residual
    /// additions start close to the identity), zero biases and an identity normalisation:
    /// where training starts.
    pub fn seeded(cfg: &Config, seed: u64) -> Result<(VarMap, Self)> {
        let varmap = VarMap::new();
        let net = Self::new(cfg, VarBuilder::from_varmap(&varmap, DTYPE, &Device::Cpu))?;
        net_core::vars::init_seeded(&varmap, seed, |name, dims| {
            if name.starts_with("norm.") {
                None
            } else if name.ends_with("bias") {
                Some(0.0)
            } else if name.ends_with(".out.weight") || name.starts_with("head.") {
                Some(0.1 * net_core::vars::glorot_bound(dims))
            } else {
                Some(net_core::vars::glorot_bound(dims))
            }
        })?;
        Ok((varmap, net))
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.cfg
    }

    /// The dropout masks' random stream (reseed it for reproducible training).
    pub fn dropout_rng(&self) -> &DropoutRng {
        &self.rng
    }

    /// `(batch, frames, features)` input frames → `(batch, frames, 3)` logits; `train`
    /// applies dropout.
    pub fn forward_t(&self, x: &Tensor, train: bool) -> Result<Tensor> {
        let (_, _, f) = x.dims3()?;
        if f != self.cfg.tcn.in_features {
            return Err(BeatNetError::Input(format!(
                "frames have {f} features, the network takes {}",
                self.cfg.tcn.in_features
            )));
        }
        let x = x
            .broadcast_sub(&self.norm_mean.detach())?
            .broadcast_div(&self.norm_std.detach())?;
        let h = self.tcn.forward_t(&x, train)?.relu()?;
        Ok(self.head.forward(&h)?)
    }

    /// Logits `(frames, 3)` of one sequence's features `(frames, in_features)`: the
    /// function [`BeatNet::forward_t`] computes without dropout, through the trunk's
    /// inference path ([`Tcn::forward_frames`]; values differ from `forward_t`'s in the
    /// last bits). For inference: no gradients.
    ///
    /// ```
    /// let (_vm, net) = beat_net::BeatNet::seeded(&Default::default(), 1)?;
    /// let x = ndarray::Array2::<f32>::zeros((40, 130));
    /// assert_eq!(net.frame_logits(x.view())?.dim(), (40, 3));
    /// # Ok::<(), beat_net::BeatNetError>(())
    /// ```
    pub fn frame_logits(&self, x: ArrayView2<f32>) -> Result<Array2<f32>> {
        let f = x.ncols();
        let (mean, std) = (
            self.norm_mean.to_vec1::<f32>()?,
            self.norm_std.to_vec1::<f32>()?,
        );
        if f != self.cfg.tcn.in_features || mean.len() != f || std.len() != f {
            return Err(BeatNetError::Input(format!(
                "frames have {f} features, the network takes {}",
                self.cfg.tcn.in_features
            )));
        }
        let mut x = x.to_owned();
        for mut row in x.rows_mut() {
            for ((v, m), s) in row.iter_mut().zip(&mean).zip(&std) {
                *v = (*v - m) / s;
            }
        }
        let mut h = self.tcn.forward_frames(x.view())?;
        h.mapv_inplace(|v| v.max(0.0));
        Ok(linear_rows(h.view(), &linear_parts(&self.head)?))
    }
}
