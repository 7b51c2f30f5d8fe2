//! The arousal CRNN of SPEC §7 in candle's model style.
//!
//! Input: `T = 20` steps of a 2 fps × 64-band mel spectrogram (dB; normalised per band by
//! statistics stored with the weights). Layers: three × (Conv 8@3×3 "same" → BatchNorm →
//! Dropout .75); reshape to `(T, 64·8)`; Dense 8 → Dropout .5; GRU 16 → Dropout .5;
//! Maxout dense (8 linear pieces, the maximum is taken) → one arousal value per step.
//! As in the SPEC (and Keras's defaults) the convolutions and the dense layer are linear.

use std::sync::Mutex;

use bowing_net::nn::{conv2d_nhwc, DropoutRng, SeededDropout};
use candle_core::{Module, Tensor, D};
use candle_nn::rnn::{GRUConfig, RNN};
use candle_nn::{Init, Linear, VarBuilder, GRU};
use serde::{Deserialize, Serialize};

use crate::error::Result;
use bowing_net::NetError;

/// The network's shape (SPEC §7 by default).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Config {
    /// Time steps per window (10 s at 2 fps).
    pub steps: usize,
    /// Mel bands.
    pub n_mels: usize,
    /// Conv blocks.
    pub conv_blocks: usize,
    /// Channels of each convolution.
    pub conv_channels: usize,
    /// Square kernel size ("same" padding).
    pub kernel_size: usize,
    /// Dropout after each conv block.
    pub conv_dropout: f32,
    /// Units of the dense layer.
    pub dense_units: usize,
    /// Dropout after the dense layer.
    pub dense_dropout: f32,
    /// GRU units.
    pub gru_units: usize,
    /// Dropout after the GRU.
    pub gru_dropout: f32,
    /// Linear pieces of the maxout output.
    pub maxout_pieces: usize,
    /// BatchNorm epsilon (Keras: 1e-3).
    pub bn_eps: f64,
    /// BatchNorm running-statistics momentum (Keras: 0.99).
    pub bn_momentum: f64,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            steps: 20,
            n_mels: 64,
            conv_blocks: 3,
            conv_channels: 8,
            kernel_size: 3,
            conv_dropout: 0.75,
            dense_units: 8,
            dense_dropout: 0.5,
            gru_units: 16,
            gru_dropout: 0.5,
            maxout_pieces: 8,
            bn_eps: 1e-3,
            bn_momentum: 0.99,
        }
    }
}

impl Config {
    /// Checks that the shape is usable.
    pub fn validate(&self) -> Result<()> {
        let positive = [
            self.steps,
            self.n_mels,
            self.conv_blocks,
            self.conv_channels,
            self.dense_units,
            self.gru_units,
            self.maxout_pieces,
        ];
        if positive.contains(&0) || self.kernel_size % 2 == 0 {
            return Err(
                NetError::Config("sizes must be positive and the kernel odd".into()).into(),
            );
        }
        for p in [self.conv_dropout, self.dense_dropout, self.gru_dropout] {
            if !(0.0..1.0).contains(&p) {
                return Err(NetError::Config(format!("dropout must be in [0, 1), got {p}")).into());
            }
        }
        Ok(())
    }
}

/// Batch normalisation over the last (channel) axis, with running statistics that a
/// training forward pass updates.
#[derive(Debug)]
pub struct BatchNormNhwc {
    gamma: Tensor,
    beta: Tensor,
    running_mean: Mutex<Tensor>,
    running_var: Mutex<Tensor>,
    eps: f64,
    momentum: f64,
    name: String,
}

impl BatchNormNhwc {
    fn new(channels: usize, eps: f64, momentum: f64, vb: VarBuilder, name: &str) -> Result<Self> {
        Ok(Self {
            gamma: vb.get_with_hints(channels, "gamma", Init::Const(1.0))?,
            beta: vb.get_with_hints(channels, "beta", Init::Const(0.0))?,
            running_mean: Mutex::new(vb.get_with_hints(
                channels,
                "running_mean",
                Init::Const(0.0),
            )?),
            running_var: Mutex::new(vb.get_with_hints(
                channels,
                "running_var",
                Init::Const(1.0),
            )?),
            eps,
            momentum,
            name: name.to_string(),
        })
    }

    fn forward_t(&self, x: &Tensor, train: bool) -> Result<Tensor> {
        let c = x.dim(D::Minus1)?;
        let (mean, var) = if train {
            // Column means as a matrix product: candle's reductions over a leading axis
            // are slow on the CPU.
            let flat = x.reshape(((), c))?;
            let n = flat.dim(0)?;
            let ones = Tensor::ones((1, n), flat.dtype(), flat.device())?;
            let mean = (ones.matmul(&flat)? / n as f64)?.squeeze(0)?;
            let centred = flat.broadcast_sub(&mean)?;
            let var = (ones.matmul(&centred.sqr()?)? / n as f64)?.squeeze(0)?;
            let m = self.momentum;
            if let (Ok(mut rm), Ok(mut rv)) = (self.running_mean.lock(), self.running_var.lock()) {
                *rm = ((rm.detach() * m)? + (mean.detach() * (1.0 - m))?)?;
                *rv = ((rv.detach() * m)? + (var.detach() * (1.0 - m))?)?;
            }
            (mean, var)
        } else {
            let rm = self.running_mean.lock().map(|t| t.clone());
            let rv = self.running_var.lock().map(|t| t.clone());
            match (rm, rv) {
                (Ok(m), Ok(v)) => (m, v),
                _ => return Err(NetError::Config("batch-norm statistics poisoned".into()).into()),
            }
        };
        let inv = (var + self.eps)?.sqrt()?.recip()?;
        Ok(x.broadcast_sub(&mean)?
            .broadcast_mul(&(inv * &self.gamma)?)?
            .broadcast_add(&self.beta)?)
    }

    /// The running statistics as `(name, tensor)` pairs (`bnK.running_mean`, `…var`).
    pub fn running_stats(&self) -> Vec<(String, Tensor)> {
        let mut out = Vec::new();
        if let Ok(m) = self.running_mean.lock() {
            out.push((format!("{}.running_mean", self.name), m.clone()));
        }
        if let Ok(v) = self.running_var.lock() {
            out.push((format!("{}.running_var", self.name), v.clone()));
        }
        out
    }
}

/// The arousal CRNN.
#[derive(Debug)]
pub struct EmotionNet {
    cfg: Config,
    convs: Vec<(Tensor, Tensor)>,
    bns: Vec<BatchNormNhwc>,
    dense: Linear,
    gru: GRU,
    maxout: Linear,
    conv_dropout: SeededDropout,
    dense_dropout: SeededDropout,
    gru_dropout: SeededDropout,
    norm_mean: Tensor,
    norm_std: Tensor,
    rng: DropoutRng,
}

impl EmotionNet {
    /// Builds the network from `vb` (names `conv{k}.{weight,bias}`,
    /// `bn{k}.{gamma,beta,running_mean,running_var}`, `dense.*`, `gru.*`, `maxout.*`,
    /// `norm.{mean,std}`).
    ///
    /// ```
    /// use candle_core::{DType, Device, Tensor};
    /// let varmap = candle_nn::VarMap::new();
    /// let vb = candle_nn::VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu);
    /// let net = emotion_net::EmotionNet::new(&Default::default(), vb)?;
    /// let x = Tensor::zeros((2, 20, 64), DType::F32, &Device::Cpu)?;
    /// assert_eq!(net.forward_t(&x, false)?.dims(), &[2, 20]);
    /// # Ok::<(), emotion_net::EmotionError>(())
    /// ```
    pub fn new(cfg: &Config, vb: VarBuilder) -> Result<Self> {
        cfg.validate()?;
        let k = cfg.kernel_size;
        let mut convs = Vec::with_capacity(cfg.conv_blocks);
        let mut bns = Vec::with_capacity(cfg.conv_blocks);
        let mut cin = 1;
        for i in 1..=cfg.conv_blocks {
            let p = vb.pp(format!("conv{i}"));
            let w = p.get_with_hints((cfg.conv_channels, cin, k, k), "weight", Init::Const(0.0))?;
            let b = p.get_with_hints(cfg.conv_channels, "bias", Init::Const(0.0))?;
            convs.push((w, b));
            let name = format!("bn{i}");
            bns.push(BatchNormNhwc::new(
                cfg.conv_channels,
                cfg.bn_eps,
                cfg.bn_momentum,
                vb.pp(&name),
                &name,
            )?);
            cin = cfg.conv_channels;
        }
        let flat = cfg.n_mels * cfg.conv_channels;
        let linear = |i: usize, o: usize, name: &str| -> Result<Linear> {
            let p = vb.pp(name);
            let w = p.get_with_hints((o, i), "weight", Init::Const(0.0))?;
            let b = p.get_with_hints(o, "bias", Init::Const(0.0))?;
            Ok(Linear::new(w, Some(b)))
        };
        let dense = linear(flat, cfg.dense_units, "dense")?;
        let gru = candle_nn::rnn::gru(
            cfg.dense_units,
            cfg.gru_units,
            GRUConfig {
                w_ih_init: Init::Const(0.0),
                w_hh_init: Init::Const(0.0),
                b_ih_init: Some(Init::Const(0.0)),
                b_hh_init: Some(Init::Const(0.0)),
            },
            vb.pp("gru"),
        )?;
        let maxout = linear(cfg.gru_units, cfg.maxout_pieces, "maxout")?;
        let norm = vb.pp("norm");
        let rng = DropoutRng::new(0);
        Ok(Self {
            cfg: cfg.clone(),
            convs,
            bns,
            dense,
            gru,
            maxout,
            conv_dropout: SeededDropout::new(cfg.conv_dropout, rng.clone()),
            dense_dropout: SeededDropout::new(cfg.dense_dropout, rng.clone()),
            gru_dropout: SeededDropout::new(cfg.gru_dropout, rng.clone()),
            norm_mean: norm.get_with_hints(cfg.n_mels, "mean", Init::Const(0.0))?,
            norm_std: norm.get_with_hints(cfg.n_mels, "std", Init::Const(1.0))?,
            rng,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.cfg
    }

    /// The dropout masks' random stream.
    pub fn dropout_rng(&self) -> &DropoutRng {
        &self.rng
    }

    /// The batch-norm running statistics (they change in training forward passes).
    pub fn running_stats(&self) -> Vec<(String, Tensor)> {
        self.bns
            .iter()
            .flat_map(BatchNormNhwc::running_stats)
            .collect()
    }

    /// `windows` `(batch, steps, n_mels)` of mel dB → `(batch, steps)` arousal. In training
    /// mode dropout is active and the batch-norm running statistics are updated.
    pub fn forward_t(&self, windows: &Tensor, train: bool) -> Result<Tensor> {
        let (b, t, m) = windows.dims3()?;
        if m != self.cfg.n_mels || t == 0 {
            return Err(NetError::Input(format!(
                "windows are {t}×{m}, the network takes steps × {} bands",
                self.cfg.n_mels
            ))
            .into());
        }
        let pad = self.cfg.kernel_size / 2;
        let mut x = windows
            .broadcast_sub(&self.norm_mean)?
            .broadcast_div(&self.norm_std)?
            .unsqueeze(3)?;
        for ((w, bias), bn) in self.convs.iter().zip(&self.bns) {
            x = conv2d_nhwc(&x, w, bias, (pad, pad))?;
            x = self
                .conv_dropout
                .forward_t(&bn.forward_t(&x, train)?, train)?;
        }
        let x = x.reshape((b, t, m * self.cfg.conv_channels))?;
        let x = self
            .dense_dropout
            .forward_t(&self.dense.forward(&x)?, train)?;
        let states = self.gru.seq(&x)?;
        let hs: Vec<Tensor> = states.iter().map(|s| s.h().clone()).collect();
        let h = Tensor::stack(&hs, 1)?;
        let h = self.gru_dropout.forward_t(&h, train)?;
        Ok(self.maxout.forward(&h)?.max(D::Minus1)?)
    }
}
