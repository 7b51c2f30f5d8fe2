//! The forward pass of [`super::Conv2dNhwc`] without im2col or GEMM packing, for unpadded
//! convolutions with 8 or 16 output channels on x86-64 CPUs with AVX2 and FMA (checked at
//! run time; other CPUs and shapes take the im2col + GEMM path; the module exists on x86-64
//! only).
//!
//! In NHWC the `kw` taps of one kernel row read one contiguous run of `kw · c` input values,
//! so an output position's sum is `kh` dot products over runs of the input, each against a
//! `(kw · c) × cout` block of the kernel matrix. A block of `R` neighbouring output positions
//! keeps its `R × cout` sums in vector registers while those runs stream past: no copy of
//! the input is made (the GEMM path copies every value `kh · kw` times into patches and
//! again into its packed panels).
//!
//! Sums start from the bias and are accumulated in the order of the kernel matrix's rows
//! with fused multiply-adds (one `vfmadd` per 8 channels), so results differ from the GEMM
//! path's in the last bits only, and do not depend on the block size. The output is
//! allocated without being zeroed: the blocks write every value of it.

use std::arch::x86_64::{
    __m256, _mm256_broadcast_ss, _mm256_fmadd_ps, _mm256_loadu_ps, _mm256_max_ps,
    _mm256_setzero_ps, _mm256_storeu_ps,
};

use rayon::prelude::*;

use super::geometry::Geometry;

/// Output rows (batch × height) per parallel task of [`DirectConv::forward`].
const ROWS_PER_TASK: usize = 8;

/// Channels per AVX vector.
const LANES: usize = 8;

/// What every output row reads: shapes, input, kernel matrix (`patch × cout`, row-major),
/// bias and whether to apply the ReLU.
struct Job<'a> {
    g: &'a Geometry,
    x: &'a [f32],
    kmat: &'a [f32],
    bias: &'a [f32],
    relu: bool,
}

/// The unsafe kernel computing one output row into the pointed-to `wo × cout` values.
type RowKernel = unsafe fn(&Job, usize, *mut f32);

/// A direct convolution whose CPU features, shapes and block size were checked: it computes
/// any output row, or the whole output.
pub(super) struct DirectConv<'a> {
    job: Job<'a>,
    kernel: RowKernel,
}

impl<'a> DirectConv<'a> {
    /// The direct convolution of `x` by `kmat` (`patch × cout`, row-major) plus `bias`
    /// (then a ReLU when `relu`), when this CPU and these shapes allow it; `None` when they
    /// do not, so the caller takes the GEMM path.
    pub(super) fn new(
        g: &'a Geometry,
        x: &'a [f32],
        kmat: &'a [f32],
        bias: &'a [f32],
        relu: bool,
    ) -> Option<Self> {
        let has_avx2_fma = std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma");
        // The kernels index with raw pointers: every length they rely on is checked here.
        let shapes_fit = g.pad_h == 0
            && g.pad_w == 0
            && g.ho + g.kh == g.h + 1
            && g.wo + g.kw == g.w + 1
            && x.len() == g.b * g.h * g.w * g.c
            && kmat.len() == g.patch() * g.cout
            && bias.len() == g.cout;
        if !has_avx2_fma || !shapes_fit {
            return None;
        }
        // Positions per block, chosen by timing on this VM (AMD EPYC, AVX2): 12 or 13
        // independent sums in flight, plus the kernel vectors and one broadcast, fit the 16
        // vector registers. For 8 channels the block that wastes the fewest positions on the
        // row's overlapping last block is taken (a 25-wide row: one block of 13, one of 12).
        let kernel: RowKernel = match g.cout {
            // Input channels known at compile time (the bowing CNN's 1 and 16) turn the
            // kernel's input offsets into constants.
            16 => match g.c {
                1 => output_row::<2, 6, 1>,
                16 => output_row::<2, 6, 16>,
                _ => output_row::<2, 6, 0>,
            },
            8 => match (
                [13, 12, 10]
                    .into_iter()
                    .min_by_key(|&r| g.wo.div_ceil(r) * r),
                g.c,
            ) {
                (Some(13), 16) => output_row::<1, 13, 16>,
                (Some(13), _) => output_row::<1, 13, 0>,
                (Some(12), _) => output_row::<1, 12, 0>,
                _ => output_row::<1, 10, 0>,
            },
            _ => return None,
        };
        let job = Job {
            g,
            x,
            kmat,
            bias,
            relu,
        };
        Some(Self { job, kernel })
    }

    /// Values per output row (`wo · cout`).
    pub(super) fn row_len(&self) -> usize {
        self.job.g.wo * self.job.g.cout
    }

    /// Output rows (`b · ho`).
    pub(super) fn rows(&self) -> usize {
        self.job.g.b * self.job.g.ho
    }

    /// Output row `row` (`image · ho + y`) into `out`; `false` (and `out` untouched) when
    /// `row` is out of range or `out` does not hold [`DirectConv::row_len`] values.
    pub(super) fn output_row(&self, row: usize, out: &mut [f32]) -> bool {
        if row >= self.rows() || out.len() != self.row_len() {
            return false;
        }
        // SAFETY: `new` saw AVX2 and FMA and checked the lengths the kernel relies on;
        // `row` and `out` were checked above.
        #[allow(unsafe_code)]
        unsafe {
            (self.kernel)(&self.job, row, out.as_mut_ptr())
        };
        true
    }

    /// The whole output (`rows × cout`), rows in parallel tasks of [`ROWS_PER_TASK`],
    /// allocated without being zeroed: the kernel writes every value.
    pub(super) fn forward(&self) -> Vec<f32> {
        let (rows, row_len) = (self.rows(), self.row_len());
        let mut out = Vec::with_capacity(rows * row_len);
        if row_len > 0 {
            out.spare_capacity_mut()[..rows * row_len]
                .par_chunks_mut(ROWS_PER_TASK * row_len)
                .enumerate()
                .for_each(|(task, chunk)| {
                    for (k, out_row) in chunk.chunks_exact_mut(row_len).enumerate() {
                        let row = task * ROWS_PER_TASK + k;
                        // SAFETY: as in `output_row`; `row < rows` and `out_row` holds
                        // `row_len` values (whole chunks of the output's rows).
                        #[allow(unsafe_code)]
                        unsafe {
                            (self.kernel)(&self.job, row, out_row.as_mut_ptr().cast::<f32>())
                        };
                    }
                });
        }
        // SAFETY: the loop above wrote every one of the first `rows × row_len` values (each
        // row's blocks cover all of its `wo` positions, `output_row` below).
        #[allow(unsafe_code)]
        unsafe {
            out.set_len(rows * row_len)
        };
        out
    }
}

/// One output row (`row = image · ho + y`): blocks of `R` positions, the last one
/// overlapping its neighbour, or single positions when the row is narrower than a block.
/// An overlapped position gets the same sum in the same order.
///
/// # Safety
/// The CPU has AVX2 and FMA, the lengths checked in [`DirectConv::new`] hold,
/// `row < b · ho` and `out` points to `wo · NV · 8` writable values.
#[allow(unsafe_code)]
#[target_feature(enable = "avx2,fma")]
unsafe fn output_row<const NV: usize, const R: usize, const C: usize>(
    job: &Job,
    row: usize,
    out: *mut f32,
) {
    let g = job.g;
    let (image, y) = (row / g.ho, row % g.ho);
    let mut xo = 0;
    // SAFETY (all three loops): a block of `r` positions from `xo` with `xo + r ≤ wo`
    // reads input rows `y .. y + kh ≤ h` and columns `xo .. xo + r − 1 + kw ≤ w` of
    // `image`, and writes positions `xo .. xo + r` of this row.
    while xo + R <= g.wo {
        unsafe { block::<NV, R, C>(job, (image, y, xo), out) };
        xo += R;
    }
    if xo < g.wo && g.wo >= R {
        unsafe { block::<NV, R, C>(job, (image, y, g.wo - R), out) };
        return;
    }
    while xo < g.wo {
        unsafe { block::<NV, 1, C>(job, (image, y, xo), out) };
        xo += 1;
    }
}

/// Output positions `xo .. xo + R` of row `y` of `image`, all `NV · 8` channels, written
/// to `out` (the row's first value).
///
/// # Safety
/// As [`output_row`], and `xo + R ≤ wo`.
#[allow(unsafe_code)]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn block<const NV: usize, const R: usize, const C: usize>(
    job: &Job,
    (image, y, xo): (usize, usize, usize),
    out: *mut f32,
) {
    let g = job.g;
    // `C` is the input's channel count when known at compile time, 0 otherwise.
    let (n, c) = (NV * LANES, if C > 0 { C } else { g.c });
    let run = g.kw * c;
    let mut bias = [_mm256_setzero_ps(); NV];
    for (v, b) in bias.iter_mut().enumerate() {
        // SAFETY: `bias` holds `cout = NV · 8` values.
        *b = unsafe { _mm256_loadu_ps(job.bias.as_ptr().add(v * LANES)) };
    }
    let mut acc: [[__m256; NV]; R] = [bias; R];
    let (x, kmat) = (job.x.as_ptr(), job.kmat.as_ptr());
    for dy in 0..g.kh {
        // SAFETY: this input row's run of positions lies inside `x` (see `output_row`).
        let inputs = unsafe { x.add(((image * g.h + y + dy) * g.w + xo) * c) };
        // SAFETY: kernel rows `dy · run .. (dy + 1) · run` of the `patch × n` matrix.
        let kernel_rows = unsafe { kmat.add(dy * run * n) };
        for q in 0..run {
            let mut k = [_mm256_setzero_ps(); NV];
            for (v, kv) in k.iter_mut().enumerate() {
                // SAFETY: inside kernel row `dy · run + q`.
                *kv = unsafe { _mm256_loadu_ps(kernel_rows.add(q * n + v * LANES)) };
            }
            for (r, a) in acc.iter_mut().enumerate() {
                // SAFETY: position `xo + r`'s tap `q` of this input row.
                let s = unsafe { _mm256_broadcast_ss(&*inputs.add(r * c + q)) };
                for (av, kv) in a.iter_mut().zip(&k) {
                    *av = _mm256_fmadd_ps(s, *kv, *av);
                }
            }
        }
    }
    let zero = _mm256_setzero_ps();
    for (r, a) in acc.iter().enumerate() {
        for (v, av) in a.iter().enumerate() {
            let value = if job.relu {
                _mm256_max_ps(*av, zero)
            } else {
                *av
            };
            // SAFETY: position `xo + r < wo` of this output row.
            unsafe { _mm256_storeu_ps(out.add((xo + r) * n + v * LANES), value) };
        }
    }
}
