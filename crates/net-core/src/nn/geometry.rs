//! The shapes of one stride-1 NHWC convolution and the index work both forward paths and
//! the backward pass share: patches (im2col), their gradients scattered back (col2im) and the
//! kernel as a `(patch, cout)` matrix.

use candle_core::bail;
use ndarray::Array2;

/// Shapes of one convolution (input `b × h × w × c`, output `b × ho × wo × cout`).
#[derive(Debug, Clone, Copy)]
pub(super) struct Geometry {
    pub(super) b: usize,
    pub(super) h: usize,
    pub(super) w: usize,
    pub(super) c: usize,
    pub(super) cout: usize,
    pub(super) kh: usize,
    pub(super) kw: usize,
    pub(super) ho: usize,
    pub(super) wo: usize,
    pub(super) pad_h: usize,
    pub(super) pad_w: usize,
}

impl Geometry {
    pub(super) fn new(
        x: &[usize],
        k: &[usize],
        pad_h: usize,
        pad_w: usize,
    ) -> candle_core::Result<Self> {
        let (&[b, h, w, c], &[cout, cin, kh, kw]) = (x, k) else {
            bail!("conv2d_nhwc: expected a 4-D input and kernel, got {x:?} and {k:?}")
        };
        if c != cin {
            bail!("conv2d_nhwc: input has {c} channels, the kernel expects {cin}")
        }
        let (hp, wp) = (h + 2 * pad_h, w + 2 * pad_w);
        if kh == 0 || kw == 0 || hp < kh || wp < kw {
            bail!("conv2d_nhwc: input {h}×{w} (padding {pad_h}, {pad_w}) is smaller than the {kh}×{kw} kernel")
        }
        Ok(Self {
            b,
            h,
            w,
            c,
            cout,
            kh,
            kw,
            ho: hp - kh + 1,
            wo: wp - kw + 1,
            pad_h,
            pad_w,
        })
    }

    pub(super) fn rows(&self) -> usize {
        self.b * self.ho * self.wo
    }

    pub(super) fn patch(&self) -> usize {
        self.kh * self.kw * self.c
    }

    /// Fills `dst` (`(r1 − r0) × patch`) with the patches of output rows `r0..r1`.
    pub(super) fn im2col(&self, x: &[f32], r0: usize, dst: &mut [f32]) {
        let patch = self.patch();
        for (k, cell) in dst.chunks_exact_mut(patch).enumerate() {
            let r = r0 + k;
            let (bi, rest) = (r / (self.ho * self.wo), r % (self.ho * self.wo));
            let (y, xo) = (rest / self.wo, rest % self.wo);
            for dy in 0..self.kh {
                let iy = y + dy;
                let row = &mut cell[dy * self.kw * self.c..(dy + 1) * self.kw * self.c];
                if iy < self.pad_h || iy >= self.h + self.pad_h {
                    row.fill(0.0);
                    continue;
                }
                let iy = iy - self.pad_h;
                // Taps dx in dx0..dx1 fall inside the row; in NHWC they are one contiguous
                // run of the input, copied at once (the others are padding).
                let dx0 = self.pad_w.saturating_sub(xo).min(self.kw);
                let dx1 = (self.w + self.pad_w).saturating_sub(xo).clamp(dx0, self.kw);
                row[..dx0 * self.c].fill(0.0);
                row[dx1 * self.c..].fill(0.0);
                if dx1 > dx0 {
                    let s = ((bi * self.h + iy) * self.w + xo + dx0 - self.pad_w) * self.c;
                    row[dx0 * self.c..dx1 * self.c]
                        .copy_from_slice(&x[s..s + (dx1 - dx0) * self.c]);
                }
            }
        }
    }

    /// Adds the patch gradients `src` of output rows `r0..` onto `gx`, the part of the input
    /// gradient that starts at element `gx_offset` (it must hold every input those rows read).
    pub(super) fn col2im(&self, src: &[f32], r0: usize, gx: &mut [f32], gx_offset: usize) {
        let patch = self.patch();
        for (k, cell) in src.chunks_exact(patch).enumerate() {
            let r = r0 + k;
            let (bi, rest) = (r / (self.ho * self.wo), r % (self.ho * self.wo));
            let (y, xo) = (rest / self.wo, rest % self.wo);
            for dy in 0..self.kh {
                let iy = y + dy;
                if iy < self.pad_h || iy >= self.h + self.pad_h {
                    continue;
                }
                let iy = iy - self.pad_h;
                for dx in 0..self.kw {
                    let ix = xo + dx;
                    if ix < self.pad_w || ix >= self.w + self.pad_w {
                        continue;
                    }
                    let d = ((bi * self.h + iy) * self.w + ix - self.pad_w) * self.c - gx_offset;
                    let s = (dy * self.kw + dx) * self.c;
                    for (o, v) in gx[d..d + self.c].iter_mut().zip(&cell[s..s + self.c]) {
                        *o += v;
                    }
                }
            }
        }
    }

    /// The kernel `(cout, c, kh, kw)` as a `(patch, cout)` matrix (patch order dy, dx, c).
    pub(super) fn kernel_matrix(&self, k: &[f32]) -> Array2<f32> {
        let mut m = Array2::<f32>::zeros((self.patch(), self.cout));
        for co in 0..self.cout {
            for ci in 0..self.c {
                for dy in 0..self.kh {
                    for dx in 0..self.kw {
                        let p = (dy * self.kw + dx) * self.c + ci;
                        m[[p, co]] = k[((co * self.c + ci) * self.kh + dy) * self.kw + dx];
                    }
                }
            }
        }
        m
    }
}
