//! The bow-change CNN of SPEC §4 in candle's model style, and its phase-tree evaluation over
//! a whole spectrogram.
//!
//! Per window (60 frames × 128 bands, "valid" convolutions as in Keras):
//! `Conv 16@5×5 → ReLU → MaxPool 2×2 → Dropout .25` → `Conv 16@5×5 → ReLU → MaxPool →
//! Dropout .25` → `Conv 8@5×5 → ReLU → MaxPool → Dropout .25` (now 4 × 12 × 8) →
//! `Dense 64 ReLU → Dropout .5 → Dense 128 ReLU → Dropout .5 → Dense 2` (+ softmax).
//!
//! Windows one frame apart share almost all of their convolution work, because convolutions
//! are translation-equivariant in time; only the 2×2 pools' alignment differs. With three
//! pools there are 8 alignments ("phases"), arranged as a binary tree: the first convolution
//! runs once over the whole spectrogram, its output is pooled at offsets 0 and 1, each of
//! those is convolved and pooled at offsets 0 and 1, and so on. The dense head then runs per
//! frame on 4 consecutive steps of the right leaf. [`BowingNet::sequence_logits`] does this;
//! it is exactly the per-window [`BowingNet::forward_t`] (tested), about 20× cheaper.

use candle_core::{DType, Device, Module, Tensor, D};
use candle_nn::{Init, Linear, VarBuilder, VarMap};
use serde::{Deserialize, Serialize};

use crate::error::{NetError, Result};
use net_core::nn::{
    conv2d_relu_nhwc, conv2d_relu_pool_phases_nhwc, max_pool2x2_nhwc, pool_phases_nhwc, DropoutRng,
    SeededDropout,
};

/// The network's shape (SPEC §4 by default).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Config {
    /// Frames per input window (2 s at 30 fps); the window of frame `t` starts at
    /// `t − window_frames/2`.
    pub window_frames: usize,
    /// Mel bands per frame.
    pub n_mels: usize,
    /// Output channels of the three convolutions.
    pub conv_channels: [usize; 3],
    /// Square kernel size of the convolutions.
    pub kernel_size: usize,
    /// Units of the two hidden dense layers.
    pub dense_units: [usize; 2],
    /// Dropout after each pool.
    pub conv_dropout: f32,
    /// Dropout after each hidden dense layer.
    pub dense_dropout: f32,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            window_frames: 60,
            n_mels: 128,
            conv_channels: [16, 16, 8],
            kernel_size: 5,
            dense_units: [64, 128],
            conv_dropout: 0.25,
            dense_dropout: 0.5,
        }
    }
}

/// Number of 2×2 pools, hence `2^POOLS` phases.
pub const POOLS: usize = 3;
/// Window alignments of the pools (`2^POOLS`).
pub const PHASES: usize = 1 << POOLS;

impl Config {
    /// `(time steps, mel steps)` after the three conv/pool stages for a window.
    pub fn trunk_output(&self) -> (usize, usize) {
        let k = self.kernel_size;
        let stage = |n: usize| n.saturating_sub(k - 1) / 2;
        let t = stage(stage(stage(self.window_frames)));
        let f = stage(stage(stage(self.n_mels)));
        (t, f)
    }

    /// Inputs of the first dense layer.
    pub fn flat_features(&self) -> usize {
        let (t, f) = self.trunk_output();
        t * f * self.conv_channels[2]
    }

    /// Offset of the classified frame inside its window.
    pub fn center_offset(&self) -> usize {
        self.window_frames / 2
    }

    /// Checks that the shape is usable.
    pub fn validate(&self) -> Result<()> {
        if self.kernel_size == 0 || self.conv_channels.contains(&0) || self.dense_units.contains(&0)
        {
            return Err(NetError::Config(
                "kernel size, channels and units must be positive".into(),
            ));
        }
        let (t, f) = self.trunk_output();
        if t == 0 || f == 0 {
            return Err(NetError::Config(format!(
                "a {}×{} window is too small for three {}×{} conv + 2×2 pool stages",
                self.window_frames, self.n_mels, self.kernel_size, self.kernel_size
            )));
        }
        for p in [self.conv_dropout, self.dense_dropout] {
            if !(0.0..1.0).contains(&p) {
                return Err(NetError::Config(format!(
                    "dropout must be in [0, 1), got {p}"
                )));
            }
        }
        Ok(())
    }
}

/// How weights are initialised (uniform, seeded; biases start at 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WeightInit {
    /// Keras's default: `±sqrt(6 / (fan_in + fan_out))`.
    #[default]
    GlorotUniform,
    /// He et al. for ReLU layers: `±sqrt(6 / fan_in)` (keeps the activations' scale through
    /// the ReLU layers).
    HeUniform,
}

impl WeightInit {
    /// The uniform bound of a weight of shape `(out, in, k…)`.
    ///
    /// ```
    /// use bowing_net::model::WeightInit;
    /// assert!((WeightInit::HeUniform.bound(&[64, 384]) - 0.125).abs() < 1e-12);
    /// ```
    pub fn bound(self, dims: &[usize]) -> f64 {
        match self {
            WeightInit::GlorotUniform => net_core::vars::glorot_bound(dims),
            WeightInit::HeUniform => {
                let fan_in: usize = dims.iter().skip(1).product();
                (6.0 / fan_in.max(1) as f64).sqrt()
            }
        }
    }
}

/// One convolution's parameters.
#[derive(Debug, Clone)]
struct Conv {
    weight: Tensor,
    bias: Tensor,
}

/// The bow-change CNN.
#[derive(Debug, Clone)]
pub struct BowingNet {
    cfg: Config,
    convs: Vec<Conv>,
    dense: Vec<Linear>,
    conv_dropout: SeededDropout,
    dense_dropout: SeededDropout,
    norm_mean: Tensor,
    norm_std: Tensor,
    rng: DropoutRng,
}

impl BowingNet {
    /// Builds the network from `vb` (names: `conv{1,2,3}.{weight,bias}`,
    /// `dense{1,2,3}.{weight,bias}`, `norm.{mean,std}` — the per-band input normalisation).
    ///
    /// ```
    /// use candle_core::{DType, Device, Tensor};
    /// let varmap = candle_nn::VarMap::new();
    /// let vb = candle_nn::VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu);
    /// let net = bowing_net::BowingNet::new(&Default::default(), vb)?;
    /// let x = Tensor::zeros((3, 60, 128), DType::F32, &Device::Cpu)?;
    /// assert_eq!(net.forward_t(&x, false)?.dims(), &[3, 2]);
    /// # Ok::<(), bowing_net::NetError>(())
    /// ```
    pub fn new(cfg: &Config, vb: VarBuilder) -> Result<Self> {
        cfg.validate()?;
        let k = cfg.kernel_size;
        let mut convs = Vec::with_capacity(3);
        let mut cin = 1;
        for (i, &cout) in cfg.conv_channels.iter().enumerate() {
            let p = vb.pp(format!("conv{}", i + 1));
            convs.push(Conv {
                weight: p.get_with_hints((cout, cin, k, k), "weight", Init::Const(0.0))?,
                bias: p.get_with_hints(cout, "bias", Init::Const(0.0))?,
            });
            cin = cout;
        }
        let sizes = [
            cfg.flat_features(),
            cfg.dense_units[0],
            cfg.dense_units[1],
            2,
        ];
        let mut dense = Vec::with_capacity(3);
        for i in 0..3 {
            let p = vb.pp(format!("dense{}", i + 1));
            let w = p.get_with_hints((sizes[i + 1], sizes[i]), "weight", Init::Const(0.0))?;
            let b = p.get_with_hints(sizes[i + 1], "bias", Init::Const(0.0))?;
            dense.push(Linear::new(w, Some(b)));
        }
        let norm = vb.pp("norm");
        let norm_mean = norm.get_with_hints(cfg.n_mels, "mean", Init::Const(0.0))?;
        let norm_std = norm.get_with_hints(cfg.n_mels, "std", Init::Const(1.0))?;
        let rng = DropoutRng::new(0);
        Ok(Self {
            cfg: cfg.clone(),
            convs,
            dense,
            conv_dropout: SeededDropout::new(cfg.conv_dropout, rng.clone()),
            dense_dropout: SeededDropout::new(cfg.dense_dropout, rng.clone()),
            norm_mean,
            norm_std,
            rng,
        })
    }

    /// A network of `cfg` in a fresh `VarMap`, with seeded uniform weights (`init`), zero
    /// biases and an identity input normalisation (mean 0, std 1): where training starts, and
    /// a stand-in for tests and benchmarks.
    ///
    /// ```
    /// use bowing_net::{model::WeightInit, BowingNet};
    /// let (varmap, net) = BowingNet::seeded(&Default::default(), WeightInit::GlorotUniform, 7)?;
    /// assert_eq!(net_core::vars::var_shapes(&varmap).len(), 14);
    /// # Ok::<(), bowing_net::NetError>(())
    /// ```
    pub fn seeded(cfg: &Config, init: WeightInit, seed: u64) -> Result<(VarMap, Self)> {
        let varmap = VarMap::new();
        let net = Self::new(cfg, VarBuilder::from_varmap(&varmap, DTYPE, &Device::Cpu))?;
        net_core::vars::init_seeded(&varmap, seed, |name, dims| {
            if name.starts_with("norm.") {
                None
            } else if name.ends_with("bias") {
                Some(0.0)
            } else {
                Some(init.bound(dims))
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

    /// `(mel_db − mean) / std` per band; `x` is `(…, n_mels)`. The statistics are constants
    /// (never trained), so no gradient flows to them, and none to the input unless the input
    /// itself asks for one (then the first convolution skips that work).
    pub fn normalise(&self, x: &Tensor) -> Result<Tensor> {
        Ok(x.broadcast_sub(&self.norm_mean.detach())?
            .broadcast_div(&self.norm_std.detach())?)
    }

    fn conv_relu(&self, i: usize, x: &Tensor) -> Result<Tensor> {
        let c = &self.convs[i];
        Ok(conv2d_relu_nhwc(x, &c.weight, &c.bias, (0, 0))?)
    }

    /// The dense head on `(…, flat_features)` → `(…, 2)` logits.
    fn head(&self, x: &Tensor, train: bool) -> Result<Tensor> {
        let mut h = x.clone();
        for (i, layer) in self.dense.iter().enumerate() {
            h = layer.forward(&h)?;
            if i < 2 {
                h = self.dense_dropout.forward_t(&h.relu()?, train)?;
            }
        }
        Ok(h)
    }

    /// Per-window forward pass: `windows` `(batch, window_frames, n_mels)` of mel dB →
    /// `(batch, 2)` logits (softmax of them = [no change, change] probabilities).
    pub fn forward_t(&self, windows: &Tensor, train: bool) -> Result<Tensor> {
        let (b, t, m) = windows.dims3()?;
        if (t, m) != (self.cfg.window_frames, self.cfg.n_mels) {
            return Err(NetError::Input(format!(
                "windows are {t}×{m}, the network takes {}×{}",
                self.cfg.window_frames, self.cfg.n_mels
            )));
        }
        let mut x = self.normalise(windows)?.unsqueeze(3)?;
        for i in 0..3 {
            x = self.conv_relu(i, &x)?;
            x = self.conv_dropout.forward_t(&max_pool2x2_nhwc(&x)?, train)?;
        }
        self.head(&x.reshape((b, self.cfg.flat_features()))?, train)
    }

    /// Logits of every window of a sequence through the phase tree (module docs).
    ///
    /// `mel` `(batch, frames, n_mels)` dB with `frames ≥ window_frames + 7`; returns
    /// `(PHASES · batch, steps, 2)` where row `r = c·4B + b·2B + a·B + i` (sequence `i`,
    /// pool offsets `a, b, c`) and step `j` is the window starting at frame
    /// `a + 2b + 4c + 8j` of sequence `i` — see [`window_start`]. Differentiable; `train`
    /// applies dropout.
    pub fn sequence_logits(&self, mel: &Tensor, train: bool) -> Result<Tensor> {
        self.phase_tree(mel, Mode::Graph { train })
    }

    /// [`BowingNet::sequence_logits`] without dropout, for inference: each convolution,
    /// its ReLU and the phase pool run as one op
    /// ([`net_core::nn::conv2d_relu_pool_phases_nhwc`]), so the convolutions' whole
    /// outputs never reach memory. The same values; no gradients.
    pub fn sequence_logits_inference(&self, mel: &Tensor) -> Result<Tensor> {
        self.phase_tree(mel, Mode::Inference)
    }

    fn phase_tree(&self, mel: &Tensor, mode: Mode) -> Result<Tensor> {
        let train = matches!(mode, Mode::Graph { train: true });
        let (_, frames, m) = mel.dims3()?;
        if m != self.cfg.n_mels || frames < self.cfg.window_frames + PHASES - 1 {
            return Err(NetError::Input(format!(
                "a {frames}×{m} sequence is too short or wide: the network needs ≥ {} frames of {} bands",
                self.cfg.window_frames + PHASES - 1,
                self.cfg.n_mels
            )));
        }
        let mut x = self.normalise(mel)?.unsqueeze(3)?;
        for i in 0..3 {
            x = match mode {
                Mode::Graph { train } => {
                    let y = self.conv_relu(i, &x)?;
                    self.conv_dropout.forward_t(&pool_phases_nhwc(&y)?, train)?
                }
                Mode::Inference => {
                    let c = &self.convs[i];
                    conv2d_relu_pool_phases_nhwc(&x, &c.weight, &c.bias)?
                }
            };
        }
        let (t3, _) = self.cfg.trunk_output();
        let (rows, steps, f3, c3) = x.dims4()?;
        if steps < t3 {
            return Err(NetError::Input("sequence too short for one window".into()));
        }
        let windows = steps - t3 + 1;
        let parts: Vec<Tensor> = (0..t3)
            .map(|k| x.narrow(1, k, windows))
            .collect::<candle_core::Result<_>>()?;
        let feats = Tensor::cat(&parts, 2)?.reshape((rows, windows, t3 * f3 * c3))?;
        self.head(&feats, train)
    }

    /// Probability of "change" from logits `(…, 2)`.
    pub fn change_probability(logits: &Tensor) -> Result<Tensor> {
        Ok(candle_nn::ops::softmax_last_dim(logits)?
            .narrow(D::Minus1, 1, 1)?
            .squeeze(D::Minus1)?)
    }
}

/// How [`BowingNet::phase_tree`] runs its convolution stages.
#[derive(Debug, Clone, Copy)]
enum Mode {
    /// candle's graph (differentiable), with dropout when `train`.
    Graph { train: bool },
    /// Fused forward-only ops.
    Inference,
}

/// Window start (frame of the padded sequence) of row `row`, step `step` of
/// [`BowingNet::sequence_logits`] for `batch` sequences; also returns the sequence index.
///
/// ```
/// // One sequence: rows are the 8 pool phases (a, b, c) = bits of the row.
/// assert_eq!(bowing_net::model::window_start(0b101, 2, 1), (0, 1 + 4 + 16));
/// ```
pub fn window_start(row: usize, step: usize, batch: usize) -> (usize, usize) {
    let seq = row % batch;
    let branch = row / batch;
    let (a, b, c) = (branch & 1, (branch >> 1) & 1, (branch >> 2) & 1);
    (seq, a + 2 * b + 4 * c + PHASES * step)
}

/// The model's variables are all f32.
pub const DTYPE: DType = DType::F32;
