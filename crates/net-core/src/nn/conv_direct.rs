//! The forward pass of [`super::Conv2dNhwc`] without im2col or GEMM packing, for unpadded
//! convolutions with 8 or 16 output channels on x86-64 CPUs with AVX2 and FMA (checked at
//! run time; other CPUs and shapes take the im2col + GEMM path; the module exists on x86-64
//! only).
//!
//! In NHWC the `kw` taps of one kernel row read one contiguous run of `kw · c` input values,
//! so an output position's sum is `kh` dot products over runs of the input, each against a
//! `(kw · c) × cout` block of the kernel matrix. A block of `R` neighbouring output positions
//! keeps its `R × cout` sums in registers while those runs stream past: no copy of the input
//! is made (the GEMM path copies every value `kh · kw` times into patches and again into
//! its packed panels, half of the bowing CNN's time).
//!
//! Sums are accumulated in the order of the kernel matrix's rows with fused multiply-adds,
//! so results differ from the GEMM path's in the last bits only.

use rayon::prelude::*;

use super::geometry::Geometry;

/// Output rows (batch × height) per parallel task.
const ROWS_PER_TASK: usize = 8;

/// What every output row reads: shapes, input, kernel matrix (`patch × cout`, row-major),
/// bias and whether to apply the ReLU.
struct Job<'a> {
    g: &'a Geometry,
    x: &'a [f32],
    kmat: &'a [f32],
    bias: &'a [f32],
    relu: bool,
}

/// Runs the direct convolution into `out` (`rows × cout`, bias added, ReLU when `relu`)
/// when this CPU and these shapes allow it; returns `false` (and leaves `out` alone) when
/// they do not, so the caller takes the GEMM path.
pub(super) fn try_forward(
    g: &Geometry,
    x: &[f32],
    kmat: &[f32],
    bias: &[f32],
    relu: bool,
    out: &mut [f32],
) -> bool {
    let has_avx2_fma =
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma");
    if g.pad_h != 0 || g.pad_w != 0 || !has_avx2_fma {
        return false;
    }
    let job = Job {
        g,
        x,
        kmat,
        bias,
        relu,
    };
    // Positions per block, chosen by timing on this VM (AMD EPYC, AVX2): 5 × 16 channels
    // and 10 × 8 keep 10 independent sums in flight; 6 × 16 spills and was twice as slow.
    match g.cout {
        16 => run::<16, 5>(&job, out),
        8 => run::<8, 10>(&job, out),
        _ => return false,
    }
    true
}

/// Splits the output into tasks of [`ROWS_PER_TASK`] output rows and runs them in parallel.
fn run<const N: usize, const R: usize>(job: &Job, out: &mut [f32]) {
    let row_len = job.g.wo * N;
    out.par_chunks_mut(ROWS_PER_TASK * row_len)
        .enumerate()
        .for_each(|(task, chunk)| {
            for (k, out_row) in chunk.chunks_exact_mut(row_len).enumerate() {
                let row = task * ROWS_PER_TASK + k;
                // SAFETY: `try_forward` only gets here after it saw AVX2 and FMA on this
                // CPU, which is all `output_row_avx2` requires.
                #[allow(unsafe_code)]
                unsafe {
                    output_row_avx2::<N, R>(job, row, out_row)
                }
            }
        });
}

/// [`output_row`] compiled for AVX2 + FMA (the compiler vectorises the channel loops).
#[target_feature(enable = "avx2,fma")]
fn output_row_avx2<const N: usize, const R: usize>(job: &Job, row: usize, out_row: &mut [f32]) {
    output_row::<N, R>(job, row, out_row)
}

/// One output row (`row = image · ho + y`): blocks of `R` positions, the last one
/// overlapping its neighbour, or single positions when the row is narrower than a block.
#[inline(always)]
fn output_row<const N: usize, const R: usize>(job: &Job, row: usize, out_row: &mut [f32]) {
    let g = job.g;
    let (image, y) = (row / g.ho, row % g.ho);
    let Ok(bias) = <&[f32; N]>::try_from(job.bias) else {
        return;
    };
    let mut xo = 0;
    while xo + R <= g.wo {
        block::<N, R>(job, bias, (image, y, xo), out_row);
        xo += R;
    }
    if xo < g.wo && g.wo >= R {
        // The last R positions again, overlapping the previous block: an overlapped
        // position gets the same sum in the same order, and a lone position's one chain
        // of dependent multiply-adds would cost as much as a whole block.
        block::<N, R>(job, bias, (image, y, g.wo - R), out_row);
        return;
    }
    while xo < g.wo {
        block::<N, 1>(job, bias, (image, y, xo), out_row);
        xo += 1;
    }
}

/// Output positions `xo .. xo + R` of row `y` of `image`, all `N` channels.
#[inline(always)]
fn block<const N: usize, const R: usize>(
    job: &Job,
    bias: &[f32; N],
    (image, y, xo): (usize, usize, usize),
    out_row: &mut [f32],
) {
    let (x, kmat) = (job.x, job.kmat);
    let (h, w, c, kh) = (job.g.h, job.g.w, job.g.c, job.g.kh);
    let run = job.g.kw * c;
    let mut acc = [*bias; R];
    for dy in 0..kh {
        let start = ((image * h + y + dy) * w + xo) * c;
        let inputs: [&[f32]; R] = std::array::from_fn(|r| &x[start + r * c..][..run]);
        let kernel_rows = &kmat[dy * run * N..(dy + 1) * run * N];
        for (q, k) in kernel_rows.chunks_exact(N).enumerate() {
            let Ok(k) = <&[f32; N]>::try_from(k) else {
                continue;
            };
            for (a, input) in acc.iter_mut().zip(&inputs) {
                let v = input[q];
                for (s, w) in a.iter_mut().zip(k) {
                    *s = v.mul_add(*w, *s);
                }
            }
        }
    }
    for (r, a) in acc.iter().enumerate() {
        let dst = &mut out_row[(xo + r) * N..(xo + r + 1) * N];
        for (d, s) in dst.iter_mut().zip(a) {
            *d = if job.relu { s.max(0.0) } else { *s };
        }
    }
}
