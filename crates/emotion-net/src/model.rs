//! The arousal CRNN of SPEC §7 in candle's model style.
//!
//! Input: `T = 20` steps of a 2 fps × 64-band mel spectrogram (dB; by default shifted so that
//! the recording's 95th-percentile frame loudness is 0 dB, then normalised per band by
//! statistics stored with the weights). Layers: three × (Conv 8@3×3 "same" with ReLU →
//! BatchNorm → Dropout .75); reshape to `(T, 64·8)`; Dense 8 → Dropout .5; GRU 16 →
//! Dropout .5; Maxout dense (8 linear pieces, the maximum is taken) → one arousal value per
//! step. The SPEC names no activation for the convolutions; the original design's layer list
//! gives ReLU for all three (and none for the dense layer, which stays linear).

use candle_core::{Module, Tensor, D};
use candle_nn::rnn::{GRUConfig, RNN};
use candle_nn::{Init, Linear, VarBuilder, GRU};
use net_core::nn::{conv2d_nhwc, DropoutRng, SeededDropout};
use serde::{Deserialize, Serialize};

use crate::batch_norm::{BatchNormNhwc, BnPass};
use crate::error::{EmotionError, Result};

/// The network's shape (SPEC §7 by default).
///
/// Fields missing from a weights file take the values older files were trained with; a field
/// this build does not know makes the file unreadable (a newer network must not be run as an
/// older one).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
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
    /// Activation of each convolution, applied before its batch norm (weights files
    /// written before this field existed read as [`ConvActivation::Linear`]).
    #[serde(default = "ConvActivation::linear")]
    pub conv_activation: ConvActivation,
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
    /// How a whole recording's level is normalised before the network sees it (weights
    /// files written before this field existed read as [`GainNorm::Absolute`]).
    #[serde(default = "GainNorm::absolute")]
    pub gain_norm: GainNorm,
}

/// The convolutions' activation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ConvActivation {
    /// None (Keras's default when no activation is named).
    #[default]
    Linear,
    /// `max(0, x)`, as the original design's layer list gives for the three convolutions.
    Relu,
}

impl ConvActivation {
    fn linear() -> Self {
        Self::Linear
    }
}

/// Level normalisation of a whole recording's mel dB spectrogram, applied before the
/// per-band standardisation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GainNorm {
    /// The dB values as computed (reference power 1): the recording's gain is seen.
    #[default]
    Absolute,
    /// Subtract the recording's frame loudness at this quantile (0..=1) of its frames, so
    /// that a recording and a louder copy of it give the same input.
    TrackQuantile(f32),
}

impl GainNorm {
    fn absolute() -> Self {
        Self::Absolute
    }

    /// The dB offset to subtract from every value of `mel_db` (`(frames, bands)`): 0 for
    /// [`GainNorm::Absolute`], else the `q`-quantile of the frames' loudness
    /// `10·log10(Σ_band 10^(dB/10))`.
    ///
    /// ```
    /// use emotion_net::model::GainNorm;
    /// let quiet = ndarray::Array2::from_shape_fn((10, 4), |(t, _)| -40.0 + t as f32);
    /// let loud = &quiet + 12.0;
    /// let q = GainNorm::TrackQuantile(0.9);
    /// let d = q.offset_db(loud.view()) - q.offset_db(quiet.view());
    /// assert!((d - 12.0).abs() < 1e-3);
    /// ```
    pub fn offset_db(self, mel_db: ndarray::ArrayView2<f32>) -> f32 {
        let Self::TrackQuantile(q) = self else {
            return 0.0;
        };
        let mut loudness: Vec<f32> = mel_db
            .rows()
            .into_iter()
            .map(|row| {
                let peak = row.iter().copied().fold(f32::NEG_INFINITY, f32::max);
                let sum: f32 = row.iter().map(|&v| 10f32.powf((v - peak) / 10.0)).sum();
                peak + 10.0 * sum.log10()
            })
            .filter(|v| v.is_finite())
            .collect();
        if loudness.is_empty() {
            return 0.0;
        }
        loudness.sort_by(f32::total_cmp);
        let k = (q.clamp(0.0, 1.0) * (loudness.len() - 1) as f32).round() as usize;
        loudness[k]
    }

    /// `mel_db` with [`GainNorm::offset_db`] subtracted.
    pub fn apply(self, mel_db: ndarray::ArrayView2<f32>) -> ndarray::Array2<f32> {
        let offset = self.offset_db(mel_db);
        mel_db.mapv(|v| v - offset)
    }
}

impl Default for Config {
    fn default() -> Self {
        Self {
            steps: 20,
            n_mels: 64,
            conv_blocks: 3,
            conv_channels: 8,
            kernel_size: 3,
            conv_activation: ConvActivation::Relu,
            conv_dropout: 0.75,
            dense_units: 8,
            dense_dropout: 0.5,
            gru_units: 16,
            gru_dropout: 0.5,
            maxout_pieces: 8,
            bn_eps: 1e-3,
            bn_momentum: 0.99,
            gain_norm: GainNorm::TrackQuantile(0.95),
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
        if positive.contains(&0) || self.kernel_size.is_multiple_of(2) {
            return Err(EmotionError::Config(
                "sizes must be positive and the kernel odd".into(),
            ));
        }
        if let GainNorm::TrackQuantile(q) = self.gain_norm {
            if !(0.0..=1.0).contains(&q) {
                return Err(EmotionError::Config(format!(
                    "the gain-normalisation quantile must be in [0, 1], got {q}"
                )));
            }
        }
        for p in [self.conv_dropout, self.dense_dropout, self.gru_dropout] {
            if !(0.0..1.0).contains(&p) {
                return Err(EmotionError::Config(format!(
                    "dropout must be in [0, 1), got {p}"
                )));
            }
        }
        Ok(())
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
            return Err(EmotionError::Input(format!(
                "windows are {t}×{m}, the network takes steps × {} bands",
                self.cfg.n_mels
            )));
        }
        let pass = if train { BnPass::Train } else { BnPass::Infer };
        let x = self.conv_stack(windows, pass)?;
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

    /// The three conv blocks: `(batch, steps, n_mels)` → `(batch, steps, n_mels, channels)`.
    /// Dropout is active only in [`BnPass::Train`].
    fn conv_stack(&self, windows: &Tensor, pass: BnPass) -> Result<Tensor> {
        let pad = self.cfg.kernel_size / 2;
        let train = pass == BnPass::Train;
        let mut x = windows
            .broadcast_sub(&self.norm_mean)?
            .broadcast_div(&self.norm_std)?
            .unsqueeze(3)?;
        for ((w, bias), bn) in self.convs.iter().zip(&self.bns) {
            x = conv2d_nhwc(&x, w, bias, (pad, pad))?;
            if self.cfg.conv_activation == ConvActivation::Relu {
                x = x.relu()?;
            }
            x = self.conv_dropout.forward_t(&bn.forward(&x, pass)?, train)?;
        }
        Ok(x)
    }

    /// Re-estimates every batch norm's running statistics as the average batch statistics
    /// of `batches` (`(batch, steps, n_mels)` windows) passed with dropout off — the inputs
    /// inference sees. Training updates them from dropped-out activations, whose spread
    /// differs ("variance shift"). Nothing else changes.
    pub fn recalibrate_batch_norm(&self, batches: &[Tensor]) -> Result<()> {
        if batches.is_empty() {
            return Ok(());
        }
        for bn in &self.bns {
            bn.start_calibration();
        }
        for b in batches {
            self.conv_stack(b, BnPass::Calibrate)?;
        }
        for bn in &self.bns {
            bn.finish_calibration()?;
        }
        Ok(())
    }
}
