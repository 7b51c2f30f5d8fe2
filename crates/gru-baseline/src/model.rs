//! The Method 1 network (SPEC §8) in candle's model style.

use std::sync::Mutex;

use candle_core::{DType, Device, Tensor, Var};
use candle_nn::{Linear, Module, VarBuilder, VarMap};
use net_core::rng::Rng;

use crate::config::Config;
use crate::error::{GruError, Result};
use crate::fused_gru::FusedGru;
use crate::norm::{MelStats, TargetSpace};

/// The hidden state of every GRU layer, `(B, H_l)` each: what a chunk hands to the next.
#[derive(Debug, Clone)]
pub struct GruState {
    /// One tensor per layer, input side first.
    pub layers: Vec<Tensor>,
}

impl GruState {
    /// The same state with the rows where `keep[b]` is false set to zero (a stream that
    /// starts a new sequence).
    pub fn reset_rows(&self, keep: &[bool]) -> Result<GruState> {
        let mut layers = Vec::with_capacity(self.layers.len());
        for h in &self.layers {
            let (batch, _) = h.dims2()?;
            if keep.len() != batch {
                return Err(GruError::Shape {
                    what: "state reset mask".into(),
                    expected: format!("{batch} rows"),
                    got: format!("{} rows", keep.len()),
                });
            }
            let mask: Vec<f32> = keep.iter().map(|&k| if k { 1.0 } else { 0.0 }).collect();
            let mask = Tensor::from_vec(mask, (batch, 1), h.device())?;
            layers.push(h.broadcast_mul(&mask)?);
        }
        Ok(GruState { layers })
    }
}

/// Method 1: mel frames `(B, T, 128)` (standardised per band) → joints `(B, T, 20)`
/// (normalised per video, see [`crate::norm`]). GRU 256 → dropout .3 → GRU 512 → dropout .3 →
/// GRU 256 → dropout .3 → dense 20.
///
/// Parameter names: `gru{l}.weight_ih_l0`, `gru{l}.weight_hh_l0`, `gru{l}.bias_ih_l0`,
/// `gru{l}.bias_hh_l0` (candle's GRU names, layer `l` from 0) and `head.weight`, `head.bias`.
///
/// ```
/// use candle_core::{DType, Device, Tensor};
/// use gru_baseline::{Config, GruBaseline};
/// let cfg = Config { hidden: vec![8, 8, 8], ..Config::default() };
/// let vars = GruBaseline::init_vars(&cfg, 7)?;
/// let net = GruBaseline::new(&cfg, candle_nn::VarBuilder::from_varmap(&vars, DType::F32, &Device::Cpu))?;
/// let x = Tensor::zeros((2, 30, 128), DType::F32, &Device::Cpu)?;
/// assert_eq!(net.forward_t(&x, false)?.dims(), &[2, 30, 20]);
/// # Ok::<(), gru_baseline::GruError>(())
/// ```
#[derive(Debug)]
pub struct GruBaseline {
    cfg: Config,
    layers: Vec<FusedGru>,
    head: Linear,
    mel_stats: MelStats,
    target: TargetSpace,
    dropout_rng: Mutex<Rng>,
}

impl GruBaseline {
    /// Builds the network from `vb` (variables are created if missing). Normalisation starts
    /// as identity / [`TargetSpace::default`]; training or [`GruBaseline::load`] sets it.
    pub fn new(cfg: &Config, vb: VarBuilder) -> Result<Self> {
        cfg.validate()?;
        let mut layers = Vec::with_capacity(cfg.hidden.len());
        let mut input = cfg.n_mels;
        for (l, &h) in cfg.hidden.iter().enumerate() {
            layers.push(FusedGru::new(input, h, vb.pp(format!("gru{l}")))?);
            input = h;
        }
        let head = candle_nn::linear(input, cfg.outputs(), vb.pp("head"))?;
        Ok(Self {
            cfg: cfg.clone(),
            layers,
            head,
            mel_stats: MelStats::identity(cfg.n_mels),
            target: TargetSpace::default(),
            dropout_rng: Mutex::new(Rng::new(0)),
        })
    }

    /// A [`VarMap`] holding freshly initialised parameters for `cfg`, drawn from `seed`
    /// (PyTorch's scheme: weights uniform in ±1/√fan, biases 0), so training is
    /// reproducible (candle's own initialisers draw from an unseeded generator).
    pub fn init_vars(cfg: &Config, seed: u64) -> Result<VarMap> {
        cfg.validate()?;
        let vars = VarMap::new();
        let mut rng = Rng::new(seed);
        let mut uniform = |shape: (usize, usize), bound: f64| -> Result<Var> {
            let data: Vec<f32> = (0..shape.0 * shape.1)
                .map(|_| rng.uniform(-bound, bound) as f32)
                .collect();
            Ok(Var::from_tensor(&Tensor::from_vec(
                data,
                shape,
                &Device::Cpu,
            )?)?)
        };
        let zeros = |n: usize| -> Result<Var> { Ok(Var::zeros(n, DType::F32, &Device::Cpu)?) };
        let mut entries: Vec<(String, Var)> = Vec::new();
        let mut input = cfg.n_mels;
        for (l, &h) in cfg.hidden.iter().enumerate() {
            let bound = 1.0 / (h as f64).sqrt();
            entries.push((
                format!("gru{l}.weight_ih_l0"),
                uniform((3 * h, input), bound)?,
            ));
            entries.push((format!("gru{l}.weight_hh_l0"), uniform((3 * h, h), bound)?));
            entries.push((format!("gru{l}.bias_ih_l0"), zeros(3 * h)?));
            entries.push((format!("gru{l}.bias_hh_l0"), zeros(3 * h)?));
            input = h;
        }
        let bound = 1.0 / (input as f64).sqrt();
        entries.push((
            "head.weight".into(),
            uniform((cfg.outputs(), input), bound)?,
        ));
        entries.push(("head.bias".into(), zeros(cfg.outputs())?));
        {
            let mut data = vars
                .data()
                .lock()
                .map_err(|_| GruError::Config("the variable map is poisoned".into()))?;
            data.extend(entries);
        }
        Ok(vars)
    }

    /// The stacked GRU layers, input side first.
    pub(crate) fn layers(&self) -> &[FusedGru] {
        &self.layers
    }

    /// The dense output layer.
    pub(crate) fn head(&self) -> &Linear {
        &self.head
    }

    /// The network's sizes.
    pub fn config(&self) -> &Config {
        &self.cfg
    }

    /// The per-band mel statistics the input is standardised with.
    pub fn mel_stats(&self) -> &MelStats {
        &self.mel_stats
    }

    /// Where outputs are de-normalised to (pixels).
    pub fn target_space(&self) -> &TargetSpace {
        &self.target
    }

    /// Sets the normalisation (from the training data, or from a weights file).
    pub fn set_normalization(&mut self, mel_stats: MelStats, target: TargetSpace) -> Result<()> {
        if mel_stats.bands() != self.cfg.n_mels || mel_stats.std.len() != self.cfg.n_mels {
            return Err(GruError::Shape {
                what: "mel statistics".into(),
                expected: format!("{} bands", self.cfg.n_mels),
                got: format!(
                    "{} means, {} stds",
                    mel_stats.mean.len(),
                    mel_stats.std.len()
                ),
            });
        }
        if mel_stats
            .mean
            .iter()
            .chain(&mel_stats.std)
            .any(|v| !v.is_finite())
            || mel_stats.std.iter().any(|&s| s <= 0.0)
        {
            return Err(GruError::Config(
                "mel normalisation values must be finite with positive scales".into(),
            ));
        }
        target.validate()?;
        self.mel_stats = mel_stats;
        self.target = target;
        Ok(())
    }

    /// Reseeds the generator of the dropout masks (training only).
    pub fn set_dropout_seed(&self, seed: u64) {
        if let Ok(mut rng) = self.dropout_rng.lock() {
            *rng = Rng::new(seed);
        }
    }

    /// `(B, T, n_mels)` standardised mel → `(B, T, 20)` normalised joints, from zero state.
    /// `train` turns dropout on.
    pub fn forward_t(&self, x: &Tensor, train: bool) -> Result<Tensor> {
        Ok(self.forward_state(x, None, train)?.0)
    }

    /// [`GruBaseline::forward_t`] from `state` (zeros when `None`), also returning the final
    /// state of every layer (detached) for the next chunk.
    pub fn forward_state(
        &self,
        x: &Tensor,
        state: Option<&GruState>,
        train: bool,
    ) -> Result<(Tensor, GruState)> {
        let (batch, steps, bands) = x.dims3()?;
        if bands != self.cfg.n_mels {
            return Err(GruError::Shape {
                what: "network input".into(),
                expected: format!("(batch, frames, {})", self.cfg.n_mels),
                got: format!("{:?}", x.dims()),
            });
        }
        if batch == 0 || steps == 0 {
            return Err(GruError::Empty("network input".into()));
        }
        if let Some(s) = state {
            if s.layers.len() != self.layers.len() {
                return Err(GruError::Shape {
                    what: "GRU state".into(),
                    expected: format!("{} layers", self.layers.len()),
                    got: format!("{} layers", s.layers.len()),
                });
            }
        }
        let mut h = x.clone();
        let mut finals = Vec::with_capacity(self.layers.len());
        for (l, layer) in self.layers.iter().enumerate() {
            h = layer.forward(&h, state.map(|s| &s.layers[l]))?;
            finals.push(FusedGru::last_state(&h)?);
            if train && self.cfg.dropout > 0.0 {
                h = self.dropout(&h)?;
            }
        }
        let last = h.dim(2)?;
        let y = self
            .head
            .forward(&h.reshape((batch * steps, last))?)?
            .reshape((batch, steps, self.cfg.outputs()))?;
        Ok((y, GruState { layers: finals }))
    }

    /// Inverted dropout with a seeded mask: zero with probability p, scale the rest 1/(1−p).
    fn dropout(&self, h: &Tensor) -> Result<Tensor> {
        let p = self.cfg.dropout;
        let keep_scale = 1.0 / (1.0 - p);
        let threshold = (f64::from(p) * (1u64 << 32) as f64) as u64;
        let n = h.elem_count();
        let mask: Vec<f32> = {
            let mut rng = self
                .dropout_rng
                .lock()
                .map_err(|_| GruError::Config("the dropout generator is poisoned".into()))?;
            let mut out = Vec::with_capacity(n);
            while out.len() < n {
                let bits = rng.next_u64();
                for half in [bits >> 32, bits & 0xFFFF_FFFF] {
                    if out.len() < n {
                        out.push(if half < threshold { 0.0 } else { keep_scale });
                    }
                }
            }
            out
        };
        let mask = Tensor::from_vec(mask, h.shape(), h.device())?;
        Ok(h.mul(&mask)?)
    }

    /// Every parameter tensor with its name (the names of [`GruBaseline::init_vars`]).
    pub fn named_parameters(&self) -> Vec<(String, Tensor)> {
        let mut out = Vec::new();
        for (l, layer) in self.layers.iter().enumerate() {
            let names = ["weight_ih_l0", "weight_hh_l0", "bias_ih_l0", "bias_hh_l0"];
            for (name, t) in names.iter().zip(layer.parameters()) {
                out.push((format!("gru{l}.{name}"), t.clone()));
            }
        }
        out.push(("head.weight".into(), self.head.weight().clone()));
        if let Some(b) = self.head.bias() {
            out.push(("head.bias".into(), b.clone()));
        }
        out
    }
}
