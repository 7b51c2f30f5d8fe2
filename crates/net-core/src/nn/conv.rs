//! 2-D convolution on channels-last (NHWC) tensors as one custom op: patches are gathered
//! (im2col) tile by tile into a small per-thread buffer and multiplied with the kernel matrix
//! (`ndarray`'s `general_mat_mul`, i.e. matrixmultiply's sgemm) straight into the output;
//! tiles run in parallel. Unpadded convolutions with 8 or 16 output channels skip both copies
//! on x86-64 CPUs with AVX2 + FMA (`conv_direct`, twice as fast for the bowing CNN). The
//! backward pass works image by image in parallel: the kernel gradient from the same
//! patches, and the input gradient by scattering the patch gradients back (col2im) into that
//! image's part of the input gradient.
//!
//! The op can apply a ReLU to its output (its backward then masks the incoming gradient by
//! the output's sign, saving candle's three element-wise passes), and skips the input
//! gradient when the input does not need one (the first layer's spectrogram). Inputs are
//! read in place from candle's storage, never copied.
//!
//! candle's CPU `conv2d` runs at about 5 GFLOP/s here, and routing the tiles through
//! candle's matmul spent a quarter of the time copying tiles into and out of tensors.

use candle_core::{bail, CpuStorage, CustomOp3, Layout, Shape, Storage, Tensor};
use ndarray::linalg::general_mat_mul;
use ndarray::{Array2, ArrayView2, ArrayViewMut2};
use rayon::prelude::*;

use super::geometry::Geometry;
use super::storage::f32_contiguous;

/// Output rows (batch × height × width positions) per tile: small enough that a tile of
/// patches stays in the core's cache between im2col and the matrix product.
const TILE_ROWS: usize = 512;

/// The convolution op: inputs `x (b, h, w, c)`, `weight (cout, c, kh, kw)`, `bias (cout)`,
/// stride 1, zero padding; output `(b, h', w', cout)`, optionally through a ReLU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Conv2dNhwc {
    /// Zeros added above and below.
    pub pad_h: usize,
    /// Zeros added left and right.
    pub pad_w: usize,
    /// Apply `max(0, ·)` to the output.
    pub relu: bool,
}

/// Runs `f` on the values of a contiguous f32 CPU tensor without copying them.
fn with_values<R>(
    t: &Tensor,
    f: impl FnOnce(&[f32]) -> candle_core::Result<R>,
) -> candle_core::Result<R> {
    let t = t.contiguous()?;
    let (storage, layout) = t.storage_and_layout();
    match &*storage {
        Storage::Cpu(cpu) => f(f32_contiguous(cpu, layout)?),
        _ => bail!("conv2d_nhwc runs on the CPU only"),
    }
}

fn shape_err(e: ndarray::ShapeError) -> candle_core::Error {
    candle_core::Error::Msg(format!("conv2d_nhwc: {e}"))
}

/// `c = a · b` (`beta = 0`) or `c += a · b` (`beta = 1`) on row-major slices.
fn matmul_into(
    a: ArrayView2<f32>,
    b: ArrayView2<f32>,
    beta: f32,
    c: &mut [f32],
) -> candle_core::Result<()> {
    let mut c = ArrayViewMut2::from_shape((a.nrows(), b.ncols()), c).map_err(shape_err)?;
    general_mat_mul(1.0, &a, &b, beta, &mut c);
    Ok(())
}

impl Conv2dNhwc {
    /// Applies the op to `x` `(b, h, w, c)` with `weight` `(cout, c, kh, kw)` and `bias`.
    pub fn apply(self, x: &Tensor, weight: &Tensor, bias: &Tensor) -> candle_core::Result<Tensor> {
        x.contiguous()?
            .apply_op3(&weight.contiguous()?, &bias.contiguous()?, self)
    }

    /// The output (`rows × cout`, bias added, ReLU applied when asked).
    fn forward(
        &self,
        g: &Geometry,
        x: &[f32],
        kmat: &Array2<f32>,
        bias: &[f32],
    ) -> candle_core::Result<Vec<f32>> {
        let (patch, cout) = (g.patch(), g.cout);
        #[cfg(target_arch = "x86_64")]
        if let Some(k) = kmat.as_slice() {
            if let Some(direct) = super::conv_direct::DirectConv::new(g, x, k, bias, self.relu) {
                return Ok(direct.forward());
            }
        }
        let mut out = vec![0.0f32; g.rows() * cout];
        out.par_chunks_mut(TILE_ROWS * cout)
            .enumerate()
            .try_for_each_init(
                || vec![0.0f32; TILE_ROWS * patch],
                |cols, (t, dst)| {
                    let n = dst.len() / cout;
                    let tile = &mut cols[..n * patch];
                    g.im2col(x, t * TILE_ROWS, tile);
                    let a = ArrayView2::from_shape((n, patch), &*tile).map_err(shape_err)?;
                    matmul_into(a, kmat.view(), 0.0, dst)?;
                    for row in dst.chunks_exact_mut(cout) {
                        for (v, b) in row.iter_mut().zip(bias) {
                            *v += b;
                            if self.relu {
                                *v = v.max(0.0);
                            }
                        }
                    }
                    Ok::<(), candle_core::Error>(())
                },
            )?;
        Ok(out)
    }

    /// Kernel and bias gradients of image `bi` (`(patch × cout)` then `cout` values) and,
    /// when `gx` is given, its input gradient; `cols` is a tile buffer.
    fn backward_image(
        &self,
        b: &Backward,
        bi: usize,
        cols: &mut [f32],
        mut gx: Option<&mut [f32]>,
    ) -> candle_core::Result<Vec<f32>> {
        let (g, x, grad, kmat_t) = (&b.geometry, b.x, b.grad, b.kmat_t);
        let (patch, cout) = (g.patch(), g.cout);
        let image_rows = g.ho * g.wo;
        let mut acc = vec![0.0f32; patch * cout + cout];
        let (gk, gb) = acc.split_at_mut(patch * cout);
        for r0 in (bi * image_rows..(bi + 1) * image_rows).step_by(TILE_ROWS) {
            let n = TILE_ROWS.min((bi + 1) * image_rows - r0);
            let g_tile = ArrayView2::from_shape((n, cout), &grad[r0 * cout..(r0 + n) * cout])
                .map_err(shape_err)?;
            for row in g_tile.rows() {
                for (a, v) in gb.iter_mut().zip(row) {
                    *a += v;
                }
            }
            let tile = &mut cols[..n * patch];
            g.im2col(x, r0, tile);
            let a = ArrayView2::from_shape((n, patch), &*tile).map_err(shape_err)?;
            matmul_into(a.t(), g_tile, 1.0, gk)?;
            if let Some(gx) = gx.as_deref_mut() {
                // The patch gradients reuse the tile buffer.
                matmul_into(g_tile, kmat_t, 0.0, tile)?;
                g.col2im(tile, r0, gx, bi * g.h * g.w * g.c);
            }
        }
        Ok(acc)
    }
}

/// What every image's backward pass reads.
struct Backward<'a> {
    geometry: Geometry,
    /// The input.
    x: &'a [f32],
    /// The gradient of the output (ReLU mask applied).
    grad: &'a [f32],
    /// The kernel matrix transposed, `(cout, patch)`.
    kmat_t: ArrayView2<'a, f32>,
}

fn values(t: &Tensor) -> candle_core::Result<Vec<f32>> {
    t.flatten_all()?.to_vec1::<f32>()
}

/// A convolution op's arguments: shapes, input, kernel matrix `(patch, cout)`, bias.
pub(super) type ConvArguments<'a> = (Geometry, &'a [f32], Array2<f32>, &'a [f32]);

/// A convolution op's arguments read in place: the shapes, the input, the kernel as a
/// `(patch, cout)` matrix and the bias (its length checked).
pub(super) fn conv_arguments<'a>(
    (xs, xl): (&'a CpuStorage, &Layout),
    (ks, kl): (&CpuStorage, &Layout),
    (bs, bl): (&'a CpuStorage, &Layout),
    (pad_h, pad_w): (usize, usize),
) -> candle_core::Result<ConvArguments<'a>> {
    let g = Geometry::new(xl.dims(), kl.dims(), pad_h, pad_w)?;
    let x = f32_contiguous(xs, xl)?;
    let bias = f32_contiguous(bs, bl)?;
    if bias.len() != g.cout {
        bail!(
            "conv2d_nhwc: bias has {} values for {} channels",
            bias.len(),
            g.cout
        )
    }
    let kmat = g.kernel_matrix(f32_contiguous(ks, kl)?);
    Ok((g, x, kmat, bias))
}

impl CustomOp3 for Conv2dNhwc {
    fn name(&self) -> &'static str {
        "conv2d-nhwc"
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
        let (g, x, kmat, bias) =
            conv_arguments((xs, xl), (ks, kl), (bs, bl), (self.pad_h, self.pad_w))?;
        let out = self.forward(&g, x, &kmat, bias)?;
        Ok((CpuStorage::F32(out), Shape::from((g.b, g.ho, g.wo, g.cout))))
    }

    fn bwd(
        &self,
        x: &Tensor,
        kernel: &Tensor,
        _bias: &Tensor,
        res: &Tensor,
        grad: &Tensor,
    ) -> candle_core::Result<(Option<Tensor>, Option<Tensor>, Option<Tensor>)> {
        let g = Geometry::new(x.dims(), kernel.dims(), self.pad_h, self.pad_w)?;
        let kmat = g.kernel_matrix(&values(kernel)?);
        let kmat_t = kmat.t();
        let mut gv = values(grad)?;
        if self.relu {
            // d relu: pass the gradient where the output is positive.
            with_values(res, |out| {
                gv.par_iter_mut()
                    .zip(out.par_iter())
                    .for_each(|(d, &o)| *d = if o > 0.0 { *d } else { 0.0 });
                Ok(())
            })?;
        }
        let (patch, cout) = (g.patch(), g.cout);
        let cols_len = TILE_ROWS.min(g.ho * g.wo) * patch;
        let input_grad = x.track_op();
        let (sums, gx) = with_values(x, |xv| {
            let bw = Backward {
                geometry: g,
                x: xv,
                grad: &gv,
                kmat_t,
            };
            let sum = |a: Vec<f32>, b: Vec<f32>| a.iter().zip(&b).map(|(p, q)| p + q).collect();
            let zero = || vec![0.0f32; patch * cout + cout];
            if input_grad {
                let mut gx = vec![0.0f32; xv.len()];
                let sums = gx
                    .par_chunks_mut(g.h * g.w * g.c)
                    .enumerate()
                    .map_init(
                        || vec![0.0f32; cols_len],
                        |cols, (bi, img)| self.backward_image(&bw, bi, cols, Some(img)),
                    )
                    .try_reduce(zero, |a, b| Ok(sum(a, b)))?;
                Ok((sums, Some(gx)))
            } else {
                let sums = (0..g.b)
                    .into_par_iter()
                    .map_init(
                        || vec![0.0f32; cols_len],
                        |cols, bi| self.backward_image(&bw, bi, cols, None),
                    )
                    .try_reduce(zero, |a, b| Ok(sum(a, b)))?;
                Ok((sums, None))
            }
        })?;
        let (gk, gb) = sums.split_at(patch * cout);
        // (patch, cout) → (cout, c, kh, kw).
        let gk = Tensor::from_slice(gk, (g.kh, g.kw, g.c, g.cout), x.device())?
            .permute((3, 2, 0, 1))?
            .contiguous()?;
        let gx = gx
            .map(|v| Tensor::from_vec(v, x.dims(), x.device()))
            .transpose()?;
        Ok((
            gx,
            Some(gk),
            Some(Tensor::from_slice(gb, g.cout, x.device())?),
        ))
    }
}

/// A stride-1 2-D convolution of `x` `(batch, height, width, in_channels)` with
/// `weight` `(out_channels, in_channels, kernel_h, kernel_w)` (candle/PyTorch layout) and
/// `bias` `(out_channels)`, zero padding `pad = (rows, columns)`; returns
/// `(batch, out_h, out_w, out_channels)`. Differentiable in `x`, `weight` and `bias`.
///
/// ```
/// use candle_core::{Device, Tensor};
/// let x = Tensor::ones((1, 4, 4, 1), candle_core::DType::F32, &Device::Cpu)?;
/// let w = Tensor::ones((2, 1, 3, 3), candle_core::DType::F32, &Device::Cpu)?;
/// let b = Tensor::zeros(2, candle_core::DType::F32, &Device::Cpu)?;
/// let y = net_core::nn::conv2d_nhwc(&x, &w, &b, (0, 0))?;
/// assert_eq!(y.dims(), &[1, 2, 2, 2]);
/// assert_eq!(y.flatten_all()?.to_vec1::<f32>()?, vec![9.0; 8]);
/// # Ok::<(), candle_core::Error>(())
/// ```
pub fn conv2d_nhwc(
    x: &Tensor,
    weight: &Tensor,
    bias: &Tensor,
    pad: (usize, usize),
) -> candle_core::Result<Tensor> {
    Conv2dNhwc {
        pad_h: pad.0,
        pad_w: pad.1,
        relu: false,
    }
    .apply(x, weight, bias)
}

/// [`conv2d_nhwc`] followed by a ReLU, as one op (one pass over the output instead of
/// candle's `relu` and its three-pass backward).
///
/// ```
/// use candle_core::{Device, Tensor};
/// let x = Tensor::ones((1, 3, 3, 1), candle_core::DType::F32, &Device::Cpu)?;
/// let w = Tensor::new(&[[[[-1f32; 3]; 3]], [[[1f32; 3]; 3]]], &Device::Cpu)?;
/// let b = Tensor::zeros(2, candle_core::DType::F32, &Device::Cpu)?;
/// let y = net_core::nn::conv2d_relu_nhwc(&x, &w, &b, (0, 0))?;
/// assert_eq!(y.flatten_all()?.to_vec1::<f32>()?, vec![0.0, 9.0]);
/// # Ok::<(), candle_core::Error>(())
/// ```
pub fn conv2d_relu_nhwc(
    x: &Tensor,
    weight: &Tensor,
    bias: &Tensor,
    pad: (usize, usize),
) -> candle_core::Result<Tensor> {
    Conv2dNhwc {
        pad_h: pad.0,
        pad_w: pad.1,
        relu: true,
    }
    .apply(x, weight, bias)
}
