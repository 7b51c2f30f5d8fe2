//! Small-batch matrix products against a weight matrix packed once (the GRU recurrence).
//!
//! The recurrence multiplies a few rows (the batch) by the same `(3H × H)` matrix at every
//! step. A general gemm re-packs the matrix on every call; here it is packed once into
//! panels of `2 × lanes` output columns (`lanes` = f32s per SIMD register, 8 with AVX2),
//! each panel holding its columns for every input index contiguously. The micro-kernel
//! keeps a tile of up to [`MAX_ROWS`] rows × one panel in registers and streams the panel
//! once per tile: two loads, `rows` broadcasts and `2 · rows` fused multiply-adds per input
//! index, the classic register-blocked sgemm kernel. SIMD is chosen at run time by `pulp`;
//! all safe code.

use pulp::{Arch, Simd, WithSimd};

/// Rows per register tile.
pub(crate) const MAX_ROWS: usize = 6;

/// Widest SIMD register in f32 lanes any `pulp` instruction set has (AVX-512; this crate
/// enables AVX2/FMA at most).
const MAX_LANES: usize = 16;

/// A matrix stored as panels for `out = x · M` products (`M` is `(k × n)`).
#[derive(Debug, Clone)]
pub(crate) struct PackedMatrix {
    k: usize,
    n: usize,
    panel: usize,
    data: Vec<f32>,
}

struct Lanes;

impl WithSimd for Lanes {
    type Output = usize;
    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) -> usize {
        S::F32_LANES
    }
}

/// Output columns per panel on this machine (two SIMD registers of the instruction set
/// `Arch::new()` detects at run time: AVX2/FMA or scalar).
fn panel_width() -> usize {
    2 * Arch::new().dispatch(Lanes)
}

impl PackedMatrix {
    /// Packs `w` `(n × k)`, row-major (a PyTorch-style weight): products give `x · wᵀ`.
    pub fn from_weight(w: &[f32], n: usize, k: usize) -> Self {
        debug_assert_eq!(w.len(), n * k);
        Self::pack(k, n, |kk, j| w[j * k + kk])
    }

    /// Packs `m` `(k × n)`, row-major: products give `x · m`.
    pub fn from_matrix(m: &[f32], k: usize, n: usize) -> Self {
        debug_assert_eq!(m.len(), k * n);
        Self::pack(k, n, |kk, j| m[kk * n + j])
    }

    fn pack(k: usize, n: usize, at: impl Fn(usize, usize) -> f32) -> Self {
        Self::pack_panels(k, n, panel_width(), at)
    }

    fn pack_panels(k: usize, n: usize, panel: usize, at: impl Fn(usize, usize) -> f32) -> Self {
        let panels = n.div_ceil(panel);
        let mut data = vec![0f32; panels * k * panel];
        for p in 0..panels {
            let block = &mut data[p * k * panel..][..k * panel];
            for kk in 0..k {
                for c in 0..panel {
                    let j = p * panel + c;
                    if j < n {
                        block[kk * panel + c] = at(kk, j);
                    }
                }
            }
        }
        Self { k, n, panel, data }
    }

    /// Inner dimension.
    pub fn k(&self) -> usize {
        self.k
    }

    /// `out (rows × n) = x (rows × k) · M`, row-major; `out` is overwritten.
    pub fn matmul(&self, x: &[f32], rows: usize, out: &mut [f32]) {
        debug_assert_eq!(x.len(), rows * self.k);
        debug_assert_eq!(out.len(), rows * self.n);
        Arch::new().dispatch(Kernel {
            m: self,
            x,
            rows,
            out,
        });
    }

    /// [`PackedMatrix::matmul`] on the instruction set `simd` (the matrix must have been
    /// packed for its width): how the tests run every path, whatever this CPU has.
    #[cfg(test)]
    fn matmul_on<S: Simd>(&self, simd: S, x: &[f32], rows: usize, out: &mut [f32]) {
        assert_eq!(self.panel, 2 * S::F32_LANES);
        simd.vectorize(Kernel {
            m: self,
            x,
            rows,
            out,
        });
    }
}

struct Kernel<'a> {
    m: &'a PackedMatrix,
    x: &'a [f32],
    rows: usize,
    out: &'a mut [f32],
}

impl WithSimd for Kernel<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) {
        let Self { m, x, rows, out } = self;
        let mut r0 = 0;
        while r0 < rows {
            let tile = (rows - r0).min(MAX_ROWS);
            let xs = &x[r0 * m.k..(r0 + tile) * m.k];
            let os = &mut out[r0 * m.n..(r0 + tile) * m.n];
            match tile {
                6 => tile_product::<S, 6>(simd, m, xs, os),
                5 => tile_product::<S, 5>(simd, m, xs, os),
                4 => tile_product::<S, 4>(simd, m, xs, os),
                3 => tile_product::<S, 3>(simd, m, xs, os),
                2 => tile_product::<S, 2>(simd, m, xs, os),
                _ => tile_product::<S, 1>(simd, m, xs, os),
            }
            r0 += tile;
        }
    }
}

/// `R` rows of `x` against every panel of `m`.
#[inline(always)]
fn tile_product<S: Simd, const R: usize>(simd: S, m: &PackedMatrix, x: &[f32], out: &mut [f32]) {
    let (k, n, panel) = (m.k, m.n, m.panel);
    debug_assert_eq!(panel, 2 * S::F32_LANES);
    let xr: [&[f32]; R] = std::array::from_fn(|r| &x[r * k..][..k]);
    for (p, block) in m.data.chunks_exact(k * panel).enumerate() {
        let (vectors, _) = S::as_simd_f32s(block);
        let mut acc = [[simd.splat_f32s(0.0); 2]; R];
        for (kk, w) in vectors.chunks_exact(2).enumerate() {
            let (w0, w1) = (w[0], w[1]);
            for r in 0..R {
                let xb = simd.splat_f32s(xr[r][kk]);
                acc[r][0] = simd.mul_add_e_f32s(xb, w0, acc[r][0]);
                acc[r][1] = simd.mul_add_e_f32s(xb, w1, acc[r][1]);
            }
        }
        let col = p * panel;
        let width = panel.min(n - col);
        for (r, a) in acc.iter().enumerate() {
            let dst = &mut out[r * n + col..][..width];
            if width == panel {
                let (d, _) = S::as_mut_simd_f32s(dst);
                d[0] = a[0];
                d[1] = a[1];
            } else {
                let mut tmp = [0f32; 2 * MAX_LANES];
                let (t, _) = S::as_mut_simd_f32s(&mut tmp[..panel]);
                t[0] = a[0];
                t[1] = a[1];
                dst.copy_from_slice(&tmp[..width]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values(len: usize, a: usize, b: usize) -> Vec<f32> {
        (0..len)
            .map(|i| ((i * a % b) as f32 - (b / 2) as f32) * 0.05)
            .collect()
    }

    /// `x (rows × k) · wᵀ` with `w` `(n × k)`, in f64.
    fn naive_product(x: &[f32], w: &[f32], rows: usize, k: usize, n: usize) -> Vec<f64> {
        let mut out = vec![0f64; rows * n];
        for r in 0..rows {
            for j in 0..n {
                out[r * n + j] = (0..k)
                    .map(|i| f64::from(x[r * k + i]) * f64::from(w[j * k + i]))
                    .sum();
            }
        }
        out
    }

    /// Runs the kernel on `simd` and compares it with the naive product.
    fn check_on<S: Simd>(simd: S) {
        for (rows, k, n) in [(1, 256, 768), (7, 13, 7), (13, 130, 37), (12, 64, 48)] {
            let x = values(rows * k, 7, 13);
            let w = values(n * k, 5, 11);
            let packed = PackedMatrix::pack_panels(k, n, 2 * S::F32_LANES, |kk, j| w[j * k + kk]);
            let mut out = vec![f32::NAN; rows * n];
            packed.matmul_on(simd, &x, rows, &mut out);
            let naive = naive_product(&x, &w, rows, k, n);
            for (got, want) in out.iter().zip(&naive) {
                assert!(
                    (f64::from(*got) - want).abs() < 1e-4 * (1.0 + want.abs()),
                    "{} lanes ({rows},{k},{n}): {got} vs {want}",
                    S::F32_LANES
                );
            }
        }
    }

    /// The kernel on every instruction set this CPU can run, not only the one `Arch::new()`
    /// picks: scalar always, and AVX2/FMA when present. (AVX-512 is not enabled: pulp's
    /// `x86-v4` feature needs rustc 1.89, above the workspace's 1.88, and measured no faster.)
    #[test]
    fn every_instruction_set_computes_the_same_product() {
        check_on(pulp::Scalar::new());
        #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
        {
            if let Some(simd) = pulp::x86::V3::try_new() {
                check_on(simd);
            }
        }
    }

    #[test]
    fn equals_the_naive_product_for_every_tile_size_and_ragged_width() {
        for (rows, k, n) in [
            (1, 512, 1536),
            (7, 13, 7),
            (6, 1, 1),
            (13, 130, 37),
            (2, 64, 48),
        ] {
            let x = values(rows * k, 7, 13);
            let w = values(n * k, 5, 11);
            let packed = PackedMatrix::from_weight(&w, n, k);
            let mut out = vec![f32::NAN; rows * n];
            packed.matmul(&x, rows, &mut out);
            // The same matrix given as (k × n): the transpose of w.
            let wt: Vec<f32> = (0..k * n).map(|i| w[(i % n) * k + i / n]).collect();
            let mut out_t = vec![f32::NAN; rows * n];
            PackedMatrix::from_matrix(&wt, k, n).matmul(&x, rows, &mut out_t);
            let naive = naive_product(&x, &w, rows, k, n);
            for r in 0..rows {
                for j in 0..n {
                    let want = naive[r * n + j];
                    for got in [out[r * n + j], out_t[r * n + j]] {
                        assert!(
                            (f64::from(got) - want).abs() < 1e-4 * (1.0 + want.abs()),
                            "({rows},{k},{n}) [{r},{j}]: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }
}
