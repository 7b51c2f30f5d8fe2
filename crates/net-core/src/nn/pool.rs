//! 2×2 max pooling (stride 2, floor) on channels-last tensors with an exact backward.
//!
//! candle 0.11's `max_pool2d` backward scaled gradients by 1/k² and misrouted them for odd
//! sizes; this op routes each output's gradient to the first maximal input of its 2×2 cell
//! (rows and columns left over by the floor get none), which `tests/gradcheck.rs` checks
//! against finite differences.

use candle_core::{bail, CpuStorage, CustomOp1, CustomOp2, Layout, Shape, Tensor};
use rayon::prelude::*;

use super::storage::f32_contiguous;

/// The forward op: `(b, h, w, c)` → `(b, h/2, w/2, c)`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MaxPool2x2;

/// Index (0..4, order top-left, top-right, bottom-left, bottom-right) of the first maximum of
/// the 2×2 cell at output `(y, x)`, channel `ch`.
#[inline]
fn argmax(src: &[f32], w: usize, c: usize, y: usize, x: usize, ch: usize) -> (usize, f32) {
    let at = |dy: usize, dx: usize| src[((2 * y + dy) * w + 2 * x + dx) * c + ch];
    let mut best = (0, at(0, 0));
    for (k, (dy, dx)) in [(0, 1), (1, 0), (1, 1)].into_iter().enumerate() {
        let v = at(dy, dx);
        if v > best.1 {
            best = (k + 1, v);
        }
    }
    best
}

/// Pools the `ho × w/2` cells of `img` (`h × w × c`, channels last; rows beyond `2·ho` unused)
/// into `dst` (`ho × w/2 × c`).
///
/// Same values as [`argmax`] per channel (the first maximum; a NaN first value stays), read
/// as four contiguous channel runs per cell so that the channel loop vectorises.
fn pool_image(img: &[f32], w: usize, c: usize, ho: usize, dst: &mut [f32]) {
    let (wo, row) = (w / 2, w * c);
    if wo == 0 || c == 0 {
        return;
    }
    for (y, dst_row) in dst.chunks_exact_mut(wo * c).take(ho).enumerate() {
        let top = &img[2 * y * row..][..row];
        let bottom = &img[(2 * y + 1) * row..][..row];
        for (x, cell) in dst_row.chunks_exact_mut(c).enumerate() {
            let (p, q) = top[2 * x * c..][..2 * c].split_at(c);
            let (r, s) = bottom[2 * x * c..][..2 * c].split_at(c);
            for ((((o, &a), &b), &d), &e) in cell.iter_mut().zip(p).zip(q).zip(r).zip(s) {
                let mut m = a;
                for v in [b, d, e] {
                    if v > m {
                        m = v;
                    }
                }
                *o = m;
            }
        }
    }
}

/// `v` if it is larger than `m`, else `m`: taken in reading order, the first maximum wins
/// and a NaN is kept only when it comes first.
#[inline(always)]
fn first_max(m: f32, v: f32) -> f32 {
    if v > m {
        v
    } else {
        m
    }
}

/// The maximum of each horizontal pair of cells of one input row (`w × c`, channels last)
/// into `dst` (`w/2 × c`).
pub(super) fn pair_max_row(row: &[f32], c: usize, dst: &mut [f32]) {
    for (x, cell) in dst.chunks_exact_mut(c).enumerate() {
        let (p, q) = row[2 * x * c..][..2 * c].split_at(c);
        for ((o, &a), &b) in cell.iter_mut().zip(p).zip(q) {
            *o = first_max(a, b);
        }
    }
}

/// Output rows per parallel task of [`PoolPhases`].
const PHASE_ROWS_PER_TASK: usize = 32;

/// Output rows `y0 ..` of both phases (`even`, `odd`: whole rows of `half` values each)
/// of one image whose input row `r`'s horizontal pair maxima `pair_maxima(r, dst)` writes
/// (`half` values): each input row's pair maxima are taken once and shared by the two
/// phases that read the row. Same values as [`pool_image`] on rows `2y, 2y + 1` (even) and
/// `2y + 1, 2y + 2` (odd) whenever no value is NaN (the first maximum of the top pair, then
/// of the bottom pair, then of the two).
pub(super) fn pool_phase_rows_with(
    mut pair_maxima: impl FnMut(usize, &mut [f32]),
    half: usize,
    y0: usize,
    even: &mut [f32],
    odd: &mut [f32],
) {
    if half == 0 {
        return;
    }
    let mut top = vec![0.0f32; half];
    let mut mid = vec![0.0f32; half];
    let mut bottom = vec![0.0f32; half];
    pair_maxima(2 * y0, &mut top);
    for (k, (e, o)) in even
        .chunks_exact_mut(half)
        .zip(odd.chunks_exact_mut(half))
        .enumerate()
    {
        let y = y0 + k;
        pair_maxima(2 * y + 1, &mut mid);
        pair_maxima(2 * y + 2, &mut bottom);
        for (((de, do_), (&t, &m)), &b) in e
            .iter_mut()
            .zip(o.iter_mut())
            .zip(top.iter().zip(&mid))
            .zip(&bottom)
        {
            *de = first_max(t, m);
            *do_ = first_max(m, b);
        }
        std::mem::swap(&mut top, &mut bottom);
    }
}

/// Runs `task(image, first output row, even rows, odd rows)` in parallel over blocks of
/// [`PHASE_ROWS_PER_TASK`] output rows of both phases of `out` (`(2b, ho, wo, c)` as
/// `2 · b · image_out` values, even phase first). Odd input rows are read by both phases,
/// so each task owns the same rows of both halves.
pub(super) fn for_phase_row_blocks(
    out: &mut [f32],
    b: usize,
    image_out: usize,
    half: usize,
    task: impl Fn(usize, usize, &mut [f32], &mut [f32]) + Sync,
) {
    if image_out == 0 || half == 0 {
        return;
    }
    let task_out = PHASE_ROWS_PER_TASK * half;
    let (even, odd) = out.split_at_mut(b * image_out);
    even.par_chunks_mut(image_out)
        .zip(odd.par_chunks_mut(image_out))
        .enumerate()
        .flat_map(|(bi, (e, o))| {
            e.par_chunks_mut(task_out)
                .zip(o.par_chunks_mut(task_out))
                .enumerate()
                .map(move |(t, pair)| (bi, t, pair))
        })
        .for_each(|(bi, t, (e, o))| task(bi, t * PHASE_ROWS_PER_TASK, e, o));
}

/// Adds `g` (the gradient of the `ho × w/2` cells [`pool_image`] made from `img`) onto `dst`
/// (laid out like `img`) at each cell's first maximum.
fn route_image(img: &[f32], g: &[f32], w: usize, c: usize, ho: usize, dst: &mut [f32]) {
    let wo = w / 2;
    for y in 0..ho {
        for x in 0..wo {
            for ch in 0..c {
                let (k, _) = argmax(img, w, c, y, x, ch);
                let (dy, dx) = (k / 2, k % 2);
                dst[((2 * y + dy) * w + 2 * x + dx) * c + ch] += g[(y * wo + x) * c + ch];
            }
        }
    }
}

impl CustomOp1 for MaxPool2x2 {
    fn name(&self) -> &'static str {
        "maxpool2x2-nhwc"
    }

    fn cpu_fwd(
        &self,
        storage: &CpuStorage,
        layout: &Layout,
    ) -> candle_core::Result<(CpuStorage, Shape)> {
        let (b, h, w, c) = layout.shape().dims4()?;
        let src = f32_contiguous(storage, layout)?;
        let (ho, wo) = (h / 2, w / 2);
        let mut out = vec![0.0f32; b * ho * wo * c];
        if !out.is_empty() {
            out.par_chunks_mut(ho * wo * c)
                .enumerate()
                .for_each(|(bi, dst)| {
                    pool_image(&src[bi * h * w * c..(bi + 1) * h * w * c], w, c, ho, dst);
                });
        }
        Ok((CpuStorage::F32(out), Shape::from((b, ho, wo, c))))
    }

    fn bwd(
        &self,
        arg: &Tensor,
        _res: &Tensor,
        grad_res: &Tensor,
    ) -> candle_core::Result<Option<Tensor>> {
        Ok(Some(arg.contiguous()?.apply_op2_no_bwd(
            &grad_res.contiguous()?,
            &MaxPool2x2Backward,
        )?))
    }
}

/// The backward op: `(input (b, h, w, c), grad of output (b, h/2, w/2, c))` → grad of input.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MaxPool2x2Backward;

impl CustomOp2 for MaxPool2x2Backward {
    fn name(&self) -> &'static str {
        "maxpool2x2-nhwc-backward"
    }

    fn cpu_fwd(
        &self,
        s1: &CpuStorage,
        l1: &Layout,
        s2: &CpuStorage,
        l2: &Layout,
    ) -> candle_core::Result<(CpuStorage, Shape)> {
        let (b, h, w, c) = l1.shape().dims4()?;
        let (gb, ho, wo, gc) = l2.shape().dims4()?;
        if (gb, ho, wo, gc) != (b, h / 2, w / 2, c) {
            bail!("maxpool backward: gradient {gb}×{ho}×{wo}×{gc} does not match input {b}×{h}×{w}×{c}")
        }
        let src = f32_contiguous(s1, l1)?;
        let grad = f32_contiguous(s2, l2)?;
        let mut out = vec![0.0f32; b * h * w * c];
        if !out.is_empty() {
            out.par_chunks_mut(h * w * c)
                .enumerate()
                .for_each(|(bi, dst)| {
                    let img = &src[bi * h * w * c..(bi + 1) * h * w * c];
                    let g = &grad[bi * ho * wo * c..(bi + 1) * ho * wo * c];
                    route_image(img, g, w, c, ho, dst);
                });
        }
        Ok((CpuStorage::F32(out), Shape::from((b, h, w, c))))
    }
}

/// 2×2 max pooling with stride 2 of `x` `(batch, height, width, channels)`; an odd last row
/// or column is dropped (floor), as Keras's `MaxPooling2D` does. Differentiable.
///
/// ```
/// use candle_core::{Device, Tensor};
/// let x = Tensor::arange(0f32, 9.0, &Device::Cpu)?.reshape((1, 3, 3, 1))?;
/// let y = net_core::nn::max_pool2x2_nhwc(&x)?;
/// assert_eq!(y.flatten_all()?.to_vec1::<f32>()?, vec![4.0]);
/// # Ok::<(), candle_core::Error>(())
/// ```
pub fn max_pool2x2_nhwc(x: &Tensor) -> candle_core::Result<Tensor> {
    x.contiguous()?.apply_op1(MaxPool2x2)
}

/// The phase tree's pooling step as one op: both 2×2 alignments in time (rows `0,1 | 2,3 …`
/// and `1,2 | 3,4 …`) of `(b, h, w, c)`, each cut to `(h − 1) / 2` rows, stacked on the batch
/// axis → `(2b, (h − 1)/2, w/2, c)` (even alignment first). Equals
/// `cat([pool(x[:, 0..2k]), pool(x[:, 1..2k+1])], 0)` with `k = (h − 1)/2`, without the
/// slices, copies and concatenation (and their backward passes).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PoolPhases;

/// Rows per phase of [`PoolPhases`] for an input of `h` rows.
pub(super) fn phase_rows(h: usize) -> usize {
    h.saturating_sub(1) / 2
}

impl CustomOp1 for PoolPhases {
    fn name(&self) -> &'static str {
        "maxpool2x2-phases-nhwc"
    }

    fn cpu_fwd(
        &self,
        storage: &CpuStorage,
        layout: &Layout,
    ) -> candle_core::Result<(CpuStorage, Shape)> {
        let (b, h, w, c) = layout.shape().dims4()?;
        let src = f32_contiguous(storage, layout)?;
        let (ho, wo) = (phase_rows(h), w / 2);
        let mut out = vec![0.0f32; 2 * b * ho * wo * c];
        let (row, half) = (w * c, wo * c);
        for_phase_row_blocks(&mut out, b, ho * half, half, |bi, y0, e, o| {
            let img = &src[bi * h * row..(bi + 1) * h * row];
            let pair_maxima =
                |r: usize, dst: &mut [f32]| pair_max_row(&img[r * row..][..row], c, dst);
            pool_phase_rows_with(pair_maxima, half, y0, e, o);
        });
        Ok((CpuStorage::F32(out), Shape::from((2 * b, ho, wo, c))))
    }

    fn bwd(
        &self,
        arg: &Tensor,
        _res: &Tensor,
        grad_res: &Tensor,
    ) -> candle_core::Result<Option<Tensor>> {
        Ok(Some(arg.contiguous()?.apply_op2_no_bwd(
            &grad_res.contiguous()?,
            &PoolPhasesBackward,
        )?))
    }
}

/// The backward op of [`PoolPhases`]: `(input (b, h, w, c), grad of output)` → grad of input
/// (both phases' gradients added).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PoolPhasesBackward;

impl CustomOp2 for PoolPhasesBackward {
    fn name(&self) -> &'static str {
        "maxpool2x2-phases-nhwc-backward"
    }

    fn cpu_fwd(
        &self,
        s1: &CpuStorage,
        l1: &Layout,
        s2: &CpuStorage,
        l2: &Layout,
    ) -> candle_core::Result<(CpuStorage, Shape)> {
        let (b, h, w, c) = l1.shape().dims4()?;
        let (ho, wo) = (phase_rows(h), w / 2);
        if l2.shape().dims4()? != (2 * b, ho, wo, c) {
            bail!(
                "phase pool backward: gradient {:?} does not match input {b}×{h}×{w}×{c}",
                l2.shape().dims()
            )
        }
        let src = f32_contiguous(s1, l1)?;
        let grad = f32_contiguous(s2, l2)?;
        let mut out = vec![0.0f32; b * h * w * c];
        if !out.is_empty() {
            out.par_chunks_mut(h * w * c)
                .enumerate()
                .for_each(|(bi, dst)| {
                    for phase in 0..2 {
                        let img = &src[bi * h * w * c + phase * w * c..(bi + 1) * h * w * c];
                        let g = &grad[(phase * b + bi) * ho * wo * c..][..ho * wo * c];
                        route_image(img, g, w, c, ho, &mut dst[phase * w * c..]);
                    }
                });
        }
        Ok((CpuStorage::F32(out), Shape::from((b, h, w, c))))
    }
}

/// Both time alignments of a 2×2 max pool stacked on the batch axis ([`PoolPhases`]).
/// Differentiable.
///
/// ```
/// use candle_core::{Device, Tensor};
/// let x = Tensor::arange(0f32, 10.0, &Device::Cpu)?.reshape((1, 5, 2, 1))?;
/// let y = net_core::nn::pool_phases_nhwc(&x)?;
/// assert_eq!(y.dims(), &[2, 2, 1, 1]);
/// assert_eq!(y.flatten_all()?.to_vec1::<f32>()?, vec![3.0, 7.0, 5.0, 9.0]);
/// # Ok::<(), candle_core::Error>(())
/// ```
pub fn pool_phases_nhwc(x: &Tensor) -> candle_core::Result<Tensor> {
    x.contiguous()?.apply_op1(PoolPhases)
}
