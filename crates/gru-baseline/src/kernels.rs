//! A small-batch matrix product for the GRU recurrence at inference time.
//!
//! With one or two rows, `x @ Wᵀ` is a matrix–vector product: candle's gemm path spends more
//! time in its per-call setup (it looks up the thread count on every call) and in its general
//! kernel than in the arithmetic, and the recurrence makes one such call per frame and layer.
//! This kernel computes four outputs at a time (four independent FMA chains sharing each load
//! of `x`) with SIMD chosen at run time by `pulp` (AVX2/FMA where present), all safe code.

use pulp::{Arch, Simd, WithSimd};

/// Rows up to which [`matmul_bt`] beats candle's gemm (measured on the 2-core Xeon).
pub(crate) const SMALL_BATCH_ROWS: usize = 2;

/// `out[r, j] = Σ_k x[r, k] · w[j, k]` for `x` `(rows, k)` and `w` `(n, k)`, both row-major;
/// `out` `(rows, n)` is overwritten.
pub(crate) fn matmul_bt(x: &[f32], rows: usize, k: usize, w: &[f32], n: usize, out: &mut [f32]) {
    debug_assert_eq!(x.len(), rows * k);
    debug_assert_eq!(w.len(), n * k);
    debug_assert_eq!(out.len(), rows * n);
    Arch::new().dispatch(MatmulBt {
        x,
        rows,
        k,
        w,
        n,
        out,
    });
}

struct MatmulBt<'a> {
    x: &'a [f32],
    rows: usize,
    k: usize,
    w: &'a [f32],
    n: usize,
    out: &'a mut [f32],
}

impl WithSimd for MatmulBt<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) {
        let Self {
            x,
            rows,
            k,
            w,
            n,
            out,
        } = self;
        for r in 0..rows {
            let xr = &x[r * k..][..k];
            let (x_head, x_tail) = S::as_simd_f32s(xr);
            let o = &mut out[r * n..][..n];
            let mut j = 0;
            while j + 4 <= n {
                let rows4 = [
                    &w[j * k..][..k],
                    &w[(j + 1) * k..][..k],
                    &w[(j + 2) * k..][..k],
                    &w[(j + 3) * k..][..k],
                ];
                let heads = rows4.map(|row| S::as_simd_f32s(row).0);
                let mut acc = [simd.splat_f32s(0.0); 4];
                for (i, xv) in x_head.iter().enumerate() {
                    for c in 0..4 {
                        acc[c] = simd.mul_add_e_f32s(heads[c][i], *xv, acc[c]);
                    }
                }
                let done = k - x_tail.len();
                for c in 0..4 {
                    let mut s = simd.reduce_sum_f32s(acc[c]);
                    for (t, xv) in x_tail.iter().enumerate() {
                        s += rows4[c][done + t] * xv;
                    }
                    o[j + c] = s;
                }
                j += 4;
            }
            while j < n {
                let row = &w[j * k..][..k];
                o[j] = row.iter().zip(xr).map(|(a, b)| a * b).sum();
                j += 1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equals_the_naive_product() {
        for (rows, k, n) in [(1, 512, 1536), (2, 13, 7), (1, 1, 1), (2, 130, 9)] {
            let x: Vec<f32> = (0..rows * k)
                .map(|i| ((i * 7 % 13) as f32 - 6.0) * 0.1)
                .collect();
            let w: Vec<f32> = (0..n * k)
                .map(|i| ((i * 5 % 11) as f32 - 5.0) * 0.05)
                .collect();
            let mut out = vec![f32::NAN; rows * n];
            matmul_bt(&x, rows, k, &w, n, &mut out);
            for r in 0..rows {
                for j in 0..n {
                    let want: f64 = (0..k)
                        .map(|i| f64::from(x[r * k + i]) * f64::from(w[j * k + i]))
                        .sum();
                    let got = f64::from(out[r * n + j]);
                    assert!(
                        (got - want).abs() < 1e-4 * (1.0 + want.abs()),
                        "({rows},{k},{n}) [{r},{j}]: {got} vs {want}"
                    );
                }
            }
        }
    }
}
