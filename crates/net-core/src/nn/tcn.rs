//! A temporal convolution network over a sequence of frame features: the trunk that the
//! frame-level networks (bow changes, strokes and strings; beats and downbeats) share.
//!
//! Input `(batch, frames, in_features)` → a linear projection to `channels` → residual
//! blocks, one per dilation `d`: `x + W₂·relu(W₁·[x(t−d), x(t), x(t+d)])` (a "same"
//! convolution of kernel 3 in time, written as shifted copies and one matrix product so
//! that it runs on candle's fast matmul, forward and backward) → `(batch, frames, channels)`.
//! The frames beyond the ends are zeros. Every output frame sees
//! `1 + 2·Σd` input frames ([`TcnConfig::receptive_field_frames`]).

use candle_core::{bail, Module, Tensor};
use candle_nn::{Linear, VarBuilder};
use ndarray::linalg::general_mat_mul;
use ndarray::{s, Array2, ArrayView1, ArrayView2};
use serde::{Deserialize, Serialize};

use super::dropout::{DropoutRng, SeededDropout};

/// The trunk's shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct TcnConfig {
    /// Features per input frame (e.g. 128 mel bands plus extra features).
    pub in_features: usize,
    /// Width of every hidden layer.
    pub channels: usize,
    /// One residual block per dilation, in order.
    pub dilations: Vec<usize>,
    /// Dropout inside each block (training only).
    pub dropout: f32,
}

impl Default for TcnConfig {
    fn default() -> Self {
        Self {
            in_features: 128,
            channels: 48,
            dilations: vec![1, 2, 4, 8, 16, 1, 2, 4, 8, 16],
            dropout: 0.1,
        }
    }
}

impl TcnConfig {
    /// Input frames that one output frame depends on.
    ///
    /// ```
    /// let cfg = net_core::nn::TcnConfig { dilations: vec![1, 2, 4], ..Default::default() };
    /// assert_eq!(cfg.receptive_field_frames(), 15);
    /// ```
    pub fn receptive_field_frames(&self) -> usize {
        1 + 2 * self.dilations.iter().sum::<usize>()
    }

    /// Why the shape cannot be built, if it cannot.
    pub fn problem(&self) -> Option<String> {
        if self.in_features == 0 || self.channels == 0 {
            return Some("in_features and channels must be positive".into());
        }
        if self.dilations.is_empty() || self.dilations.contains(&0) {
            return Some("dilations must be a non-empty list of positive steps".into());
        }
        if !(0.0..1.0).contains(&self.dropout) {
            return Some(format!("dropout must be in [0, 1), got {}", self.dropout));
        }
        None
    }
}

struct Block {
    dilation: usize,
    mix: Linear,
    out: Linear,
}

/// The trunk (see the module docs). Variables: `input.{weight,bias}`,
/// `block{i}.mix.{weight,bias}` (`channels × 3·channels`), `block{i}.out.{weight,bias}`.
pub struct Tcn {
    input: Linear,
    blocks: Vec<Block>,
    dropout: SeededDropout,
}

/// `x` delayed by `shift` frames along dim 1 (`y[t] = x[t − shift]`, zeros outside); a
/// negative shift looks ahead.
fn shifted(x: &Tensor, shift: isize) -> candle_core::Result<Tensor> {
    let (b, t, c) = x.dims3()?;
    let s = shift.unsigned_abs();
    if s == 0 {
        return Ok(x.clone());
    }
    if s >= t {
        return x.zeros_like();
    }
    let zeros = Tensor::zeros((b, s, c), x.dtype(), x.device())?;
    if shift > 0 {
        Tensor::cat(&[&zeros, &x.narrow(1, 0, t - s)?], 1)
    } else {
        Tensor::cat(&[&x.narrow(1, s, t - s)?, &zeros], 1)
    }
}

impl Tcn {
    /// Builds the trunk's variables under `vb`; dropout masks come from `rng`.
    pub fn new(cfg: &TcnConfig, vb: VarBuilder, rng: DropoutRng) -> candle_core::Result<Self> {
        if let Some(p) = cfg.problem() {
            return Err(candle_core::Error::Msg(format!("TCN config: {p}")));
        }
        let c = cfg.channels;
        let input = candle_nn::linear(cfg.in_features, c, vb.pp("input"))?;
        let blocks = cfg
            .dilations
            .iter()
            .enumerate()
            .map(|(i, &dilation)| {
                let vb = vb.pp(format!("block{i}"));
                Ok(Block {
                    dilation,
                    mix: candle_nn::linear(3 * c, c, vb.pp("mix"))?,
                    out: candle_nn::linear(c, c, vb.pp("out"))?,
                })
            })
            .collect::<candle_core::Result<Vec<_>>>()?;
        Ok(Self {
            input,
            blocks,
            dropout: SeededDropout::new(cfg.dropout, rng),
        })
    }

    /// `(batch, frames, in_features)` → `(batch, frames, channels)`; `train` applies dropout.
    pub fn forward_t(&self, x: &Tensor, train: bool) -> candle_core::Result<Tensor> {
        let mut h = self.input.forward(x)?;
        for block in &self.blocks {
            let d = block.dilation as isize;
            let taps = Tensor::cat(&[&shifted(&h, d)?, &h, &shifted(&h, -d)?], 2)?;
            let inner = block.mix.forward(&taps)?.relu()?;
            let inner = self.dropout.forward_t(&inner, train)?;
            h = (h + block.out.forward(&inner)?)?;
        }
        Ok(h)
    }
}

/// A linear layer's weight `(out, in)` and bias (zeros when it has none) as ndarray values.
pub fn linear_parts(layer: &Linear) -> candle_core::Result<(Array2<f32>, Vec<f32>)> {
    let w = layer.weight();
    let (out, inputs) = w.dims2()?;
    let values = w.flatten_all()?.to_vec1::<f32>()?;
    let w = Array2::from_shape_vec((out, inputs), values)
        .map_err(|e| candle_core::Error::Msg(format!("linear layer: {e}")))?;
    let bias = match layer.bias() {
        Some(b) => b.to_vec1::<f32>()?,
        None => vec![0.0; out],
    };
    Ok((w, bias))
}

/// `dst`'s rows set to `bias` (`fill`) or with `bias` added.
fn add_rows(dst: &mut Array2<f32>, bias: &[f32], fill: bool) {
    let bias = ArrayView1::from(bias);
    for mut row in dst.rows_mut() {
        if fill {
            row.assign(&bias);
        } else {
            row += &bias;
        }
    }
}

/// `x · layer_weightᵀ + bias` for the rows of `x` (`(rows, in)` → `(rows, out)`), with
/// [`linear_parts`]' values.
pub fn linear_rows(x: ArrayView2<f32>, (w, bias): &(Array2<f32>, Vec<f32>)) -> Array2<f32> {
    let mut y = Array2::zeros((x.nrows(), w.nrows()));
    add_rows(&mut y, bias, true);
    general_mat_mul(1.0, &x, &w.t(), 1.0, &mut y);
    y
}

/// Softmax of one row of logits, in place (the maximum subtracted first, as candle's
/// `softmax` does).
///
/// ```
/// let mut row = [0.0f32, 0.0, (2.0f32).ln()];
/// net_core::nn::softmax_in_place(&mut row);
/// assert!((row[2] - 0.5).abs() < 1e-6 && (row[0] - 0.25).abs() < 1e-6);
/// ```
pub fn softmax_in_place(row: &mut [f32]) {
    let top = row.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    for v in row.iter_mut() {
        *v = (*v - top).exp();
    }
    let sum: f32 = row.iter().sum();
    for v in row.iter_mut() {
        *v /= sum;
    }
}

impl Tcn {
    /// One sequence `(frames, in_features)` through the trunk without dropout →
    /// `(frames, channels)`: the function [`Tcn::forward_t`] computes with `train = false`,
    /// for inference (no gradients). The products accumulate in place (ndarray's
    /// `general_mat_mul`): a block's three taps read row-shifted views of the hidden
    /// state instead of shifted copies, and the residual is the output product's
    /// accumulator. Sums run in another order than candle's, so values differ from
    /// [`Tcn::forward_t`]'s in the last bits.
    pub fn forward_frames(&self, x: ArrayView2<f32>) -> candle_core::Result<Array2<f32>> {
        let input = linear_parts(&self.input)?;
        if x.ncols() != input.0.ncols() {
            bail!(
                "TCN: {} features per frame, the trunk reads {}",
                x.ncols(),
                input.0.ncols()
            )
        }
        let (t, c) = (x.nrows(), input.0.nrows());
        let mut h = linear_rows(x, &input);
        let mut mix = Array2::<f32>::zeros((t, c));
        for block in &self.blocks {
            let (w_mix, b_mix) = linear_parts(&block.mix)?;
            let (w_out, b_out) = linear_parts(&block.out)?;
            if w_mix.dim() != (c, 3 * c) || w_out.dim() != (c, c) {
                bail!(
                    "TCN: a block's weights are {:?} and {:?}",
                    w_mix.dim(),
                    w_out.dim()
                )
            }
            let tap = |k: usize| w_mix.slice(s![.., k * c..(k + 1) * c]);
            let d = block.dilation.min(t);
            add_rows(&mut mix, &b_mix, true);
            // mix[t] += W₀·h[t − d] + W₁·h[t] + W₂·h[t + d] (zeros beyond the ends).
            let (w0, w1, w2) = (tap(0), tap(1), tap(2));
            let mut late = mix.slice_mut(s![d.., ..]);
            general_mat_mul(1.0, &h.slice(s![..t - d, ..]), &w0.t(), 1.0, &mut late);
            general_mat_mul(1.0, &h, &w1.t(), 1.0, &mut mix);
            let mut early = mix.slice_mut(s![..t - d, ..]);
            general_mat_mul(1.0, &h.slice(s![d.., ..]), &w2.t(), 1.0, &mut early);
            mix.mapv_inplace(|v| v.max(0.0));
            add_rows(&mut h, &b_out, false);
            general_mat_mul(1.0, &mix, &w_out.t(), 1.0, &mut h);
        }
        Ok(h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use candle_core::{DType, Device};
    use candle_nn::VarMap;

    fn trunk(dilations: Vec<usize>) -> (Tcn, TcnConfig) {
        let cfg = TcnConfig {
            in_features: 5,
            channels: 4,
            dilations,
            dropout: 0.0,
        };
        let varmap = VarMap::new();
        let vb = VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu);
        let tcn = Tcn::new(&cfg, vb, DropoutRng::new(3)).unwrap();
        // Seeded weights, so every run checks the same network.
        crate::vars::init_seeded(&varmap, 11, |name, dims| {
            Some(if name.ends_with("bias") {
                0.1
            } else {
                crate::vars::glorot_bound(dims)
            })
        })
        .unwrap();
        (tcn, cfg)
    }

    #[test]
    fn shapes_and_receptive_field() {
        let (tcn, cfg) = trunk(vec![1, 2]);
        assert_eq!(cfg.receptive_field_frames(), 7);
        let x = crate::gradcheck::uniform_tensor(&[2, 20, 5], 1, 1.0).unwrap();
        let y = tcn.forward_t(&x, false).unwrap();
        assert_eq!(y.dims(), &[2, 20, 4]);
        // Changing frame 10 may change outputs 7..=13 only (a ReLU may hide it at the
        // edges of that range, never outside it), and changes its own output.
        let mut v = x.to_vec3::<f32>().unwrap();
        v[0][10][0] += 1.0;
        let x2 = Tensor::new(v, &Device::Cpu).unwrap();
        let y2 = tcn.forward_t(&x2, false).unwrap();
        let diff = (y2 - &y).unwrap().abs().unwrap().sum(2).unwrap();
        let diff = diff.to_vec2::<f32>().unwrap();
        for (t, d) in diff[0].iter().enumerate() {
            if !(7..=13).contains(&t) {
                assert_eq!(*d, 0.0, "frame {t}");
            }
        }
        assert!(diff[0][10] > 0.0);
        assert!(diff[1].iter().all(|d| *d == 0.0));
    }

    #[test]
    fn forward_frames_equals_forward_t() {
        for (dilations, frames) in [(vec![1, 2], 20), (vec![4, 16], 9), (vec![1], 1)] {
            let (tcn, _) = trunk(dilations);
            let x = crate::gradcheck::uniform_tensor(&[1, frames, 5], 6, 1.0).unwrap();
            let reference = tcn.forward_t(&x, false).unwrap().squeeze(0).unwrap();
            let reference = reference.to_vec2::<f32>().unwrap();
            let rows = x.squeeze(0).unwrap().to_vec2::<f32>().unwrap();
            let x = Array2::from_shape_fn((frames, 5), |(t, f)| rows[t][f]);
            let fast = tcn.forward_frames(x.view()).unwrap();
            assert_eq!(fast.dim(), (frames, 4));
            for (t, row) in reference.iter().enumerate() {
                for (ch, v) in row.iter().enumerate() {
                    let diff = (fast[[t, ch]] - v).abs();
                    assert!(
                        diff < 1e-5,
                        "frame {t} channel {ch}: {} vs {v}",
                        fast[[t, ch]]
                    );
                }
            }
        }
        let (tcn, _) = trunk(vec![1]);
        assert!(tcn.forward_frames(Array2::zeros((3, 4)).view()).is_err());
    }

    #[test]
    fn short_sequences_and_bad_configs() {
        let (tcn, _) = trunk(vec![8]);
        let x = crate::gradcheck::uniform_tensor(&[1, 3, 5], 2, 1.0).unwrap();
        assert_eq!(tcn.forward_t(&x, false).unwrap().dims(), &[1, 3, 4]);
        for bad in [
            TcnConfig {
                dilations: vec![],
                ..Default::default()
            },
            TcnConfig {
                dilations: vec![0],
                ..Default::default()
            },
            TcnConfig {
                channels: 0,
                ..Default::default()
            },
            TcnConfig {
                dropout: 1.0,
                ..Default::default()
            },
        ] {
            assert!(bad.problem().is_some(), "{bad:?}");
        }
    }

    #[test]
    fn gradients_match_finite_differences() {
        let (tcn, _) = trunk(vec![1, 3]);
        let x = crate::gradcheck::uniform_tensor(&[1, 9, 5], 4, 1.0).unwrap();
        let checked = crate::gradcheck::check_input_gradient(
            &x,
            &|x| tcn.forward_t(x, false),
            45,
            2e-2,
            1e-3,
        )
        .unwrap();
        assert!(checked >= 40, "{checked}");
    }
}
