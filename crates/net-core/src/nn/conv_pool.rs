//! A convolution + ReLU followed by both time alignments of a 2×2 max pool
//! ([`super::pool_phases_nhwc`]), as one forward-only op for inference: the phase tree's
//! stage without the convolution's whole output in memory.
//!
//! Tasks of 32 pooled rows compute the convolution's rows they need one at a time (the
//! direct kernel of `conv_direct`), take each row's horizontal pair maxima at once and
//! emit both phases' pooled rows; the full-size convolution output (the bowing CNN's first
//! is 124 bands × 16 channels per frame) is never written to memory and read back. Values
//! are bit-identical to the two ops. CPUs or shapes without the direct kernel run the two
//! ops. There is no backward pass: training uses the two differentiable ops.

use candle_core::{bail, CpuStorage, CustomOp3, Layout, Shape, Tensor};

use super::conv::{conv_arguments, Conv2dNhwc};
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_imports))]
use super::pool::{for_phase_row_blocks, pair_max_row, phase_rows, pool_phase_rows_with};

/// The fused op: inputs `x (b, h, w, c)`, `weight (cout, c, kh, kw)`, `bias (cout)`;
/// output `(2b, (h' − 1)/2, w'/2, cout)` where `h' × w'` is the unpadded convolution's size.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct ConvReluPoolPhases;

impl CustomOp3 for ConvReluPoolPhases {
    fn name(&self) -> &'static str {
        "conv2d-relu-pool-phases-nhwc"
    }

    fn cpu_fwd(
        &self,
        xs: &CpuStorage,
        xl: &Layout,
        ks: &CpuStorage,
        kl: &Layout,
        bs: &CpuStorage,
        bl: &Layout,
    ) -> candle_core::Result<(CpuStorage, Shape)> {
        let (g, x, kmat, bias) = conv_arguments((xs, xl), (ks, kl), (bs, bl), (0, 0))?;
        let (hp, wp) = (phase_rows(g.ho), g.wo / 2);
        let shape = Shape::from((2 * g.b, hp, wp, g.cout));
        #[cfg(target_arch = "x86_64")]
        if let Some(k) = kmat.as_slice() {
            if let Some(direct) = super::conv_direct::DirectConv::new(&g, x, k, bias, true) {
                let (half, c) = (wp * g.cout, g.cout);
                let mut out = vec![0.0f32; 2 * g.b * hp * half];
                for_phase_row_blocks(&mut out, g.b, hp * half, half, |image, y0, e, o| {
                    let mut conv_row = vec![0.0f32; direct.row_len()];
                    let pair_maxima = |r: usize, dst: &mut [f32]| {
                        if direct.output_row(image * g.ho + r, &mut conv_row) {
                            pair_max_row(&conv_row, c, dst);
                        }
                    };
                    pool_phase_rows_with(pair_maxima, half, y0, e, o);
                });
                return Ok((CpuStorage::F32(out), shape));
            }
        }
        bail!("conv2d_relu_pool_phases_nhwc: no direct kernel for these shapes on this CPU")
    }
}

/// [`super::conv2d_relu_nhwc`] (unpadded) then [`super::pool_phases_nhwc`], for inference:
/// the same values, without the convolution's output in memory when the direct kernel
/// applies (x86-64 with AVX2 and FMA, 8 or 16 output channels); otherwise the two ops.
/// Not differentiable.
///
/// ```
/// use candle_core::{Device, Tensor};
/// let x = Tensor::arange(0f32, 70.0, &Device::Cpu)?.reshape((1, 7, 10, 1))?;
/// let w = Tensor::ones((8, 1, 3, 3), candle_core::DType::F32, &Device::Cpu)?;
/// let b = Tensor::zeros(8, candle_core::DType::F32, &Device::Cpu)?;
/// let fused = net_core::nn::conv2d_relu_pool_phases_nhwc(&x, &w, &b)?;
/// let two_ops = net_core::nn::pool_phases_nhwc(&net_core::nn::conv2d_relu_nhwc(&x, &w, &b, (0, 0))?)?;
/// assert_eq!(fused.dims(), &[2, 2, 4, 8]);
/// assert_eq!(fused.flatten_all()?.to_vec1::<f32>()?, two_ops.flatten_all()?.to_vec1::<f32>()?);
/// # Ok::<(), candle_core::Error>(())
/// ```
pub fn conv2d_relu_pool_phases_nhwc(
    x: &Tensor,
    weight: &Tensor,
    bias: &Tensor,
) -> candle_core::Result<Tensor> {
    let (x, weight, bias) = (x.contiguous()?, weight.contiguous()?, bias.contiguous()?);
    match x.apply_op3_no_bwd(&weight, &bias, &ConvReluPoolPhases) {
        Ok(y) => Ok(y),
        Err(_) => {
            let conv = Conv2dNhwc {
                pad_h: 0,
                pad_w: 0,
                relu: true,
            };
            super::pool_phases_nhwc(&conv.apply(&x, &weight, &bias)?)
        }
    }
}
