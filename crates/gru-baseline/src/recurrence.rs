//! The GRU recurrence over all time steps as ONE candle custom op, with a hand-written
//! backward pass (back-propagation through time), and the plain-slice loops behind it that
//! inference uses directly.
//!
//! Built from candle's ordinary ops, a GRU unrolled over `T` steps makes ~15 graph nodes
//! per step and layer; candle's backward of each per-step slice of the input projection
//! allocates and adds a tensor as large as the whole sequence (O(T²) work), and its graph
//! walk recurses once per node. This op keeps the graph at one node per layer: the forward
//! runs the loop on plain slices (one `(B × H) · (H × 3H)` product per step against a
//! matrix packed once, [`PackedMatrix`]), the backward recomputes the gates with one
//! `(T·B × H) · (H × 3H)` matmul, walks back in time with one `(B × 3H) · (3H × H)` product
//! per step, and gets `∂L/∂W_hh` with one final matmul. Batch rows are independent, so both
//! directions split them over the rayon threads (no synchronisation inside the time loop).
//!
//! Layout: **batch-major**, row `b` at step `t` is at `b·T + t`. Gates follow PyTorch /
//! candle (`r, z, n` order, `b_hh` inside the reset product):
//! `r = σ(x_r + W_hr h + b_hr)`, `z = σ(x_z + W_hz h + b_hz)`,
//! `n = tanh(x_n + r ⊙ (W_hn h + b_hn))`, `h' = (1 − z) ⊙ n + z ⊙ h`, where `x = W_ih x_t + b_ih`
//! is computed for all steps beforehand (see [`crate::FusedGru`]).

use candle_core::{bail, CpuStorage, CustomOp3, Device, Layout, Shape, Tensor};
use pulp::{Arch, Simd, WithSimd};
use rayon::prelude::*;

use crate::gates::{gate_row, sigmoid, tanh, Biases};
use crate::packed::PackedMatrix;

/// The recurrence of one GRU layer: inputs `xw` `(B, T, 3H)` (input projection incl. `b_ih`),
/// `w_hh` `(3H, H)`, `b_hh` `(3H)`; output all hidden states `(B, T, H)`.
pub(crate) struct GruRecurrence {
    pub steps: usize,
    pub batch: usize,
    pub hidden: usize,
    /// Initial state `(B, H)`, row-major; `None` = zeros. Treated as a constant (detached).
    pub h0: Option<Vec<f32>>,
}

fn f32_slice<'a>(s: &'a CpuStorage, l: &Layout, what: &str) -> candle_core::Result<&'a [f32]> {
    let data = match s {
        CpuStorage::F32(v) => v.as_slice(),
        _ => bail!("gru recurrence: {what} must be f32"),
    };
    match l.contiguous_offsets() {
        Some((a, b)) => Ok(&data[a..b]),
        None => bail!("gru recurrence: {what} must be contiguous"),
    }
}

/// Rows per parallel part: the batch split evenly over the rayon threads.
fn rows_per_part(batch: usize) -> usize {
    batch.div_ceil(rayon::current_num_threads().clamp(1, batch.max(1)))
}

/// The forward loop for `rows` rows (batch-major `xw` `(rows, steps, 3H)`, `out`
/// `(rows, steps, H)`), from `h0` `(rows, H)` or zeros, on the calling thread.
pub(crate) fn forward_rows(
    xw: &[f32],
    h0: Option<&[f32]>,
    steps: usize,
    w_hh: &PackedMatrix,
    bias: &Biases,
    out: &mut [f32],
) {
    Arch::new().dispatch(ForwardLoop {
        xw,
        h0,
        steps,
        w_hh,
        bias,
        out,
    });
}

/// [`forward_rows`] as a `pulp` kernel: compiled for the machine's SIMD (AVX2/FMA), so the
/// element-wise gate loops vectorise, `fast_exp` included.
struct ForwardLoop<'a> {
    xw: &'a [f32],
    h0: Option<&'a [f32]>,
    steps: usize,
    w_hh: &'a PackedMatrix,
    bias: &'a Biases,
    out: &'a mut [f32],
}

impl WithSimd for ForwardLoop<'_> {
    type Output = ();
    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        forward_rows_inner(self.xw, self.h0, self.steps, self.w_hh, self.bias, self.out);
    }
}

#[inline(always)]
fn forward_rows_inner(
    xw: &[f32],
    h0: Option<&[f32]>,
    steps: usize,
    w_hh: &PackedMatrix,
    bias: &Biases,
    out: &mut [f32],
) {
    let hidden = w_hh.k();
    let g3 = 3 * hidden;
    let rows = out.len() / (steps * hidden).max(1);
    let mut h = match h0 {
        Some(h0) => h0.to_vec(),
        None => vec![0f32; rows * hidden],
    };
    let mut h_new = vec![0f32; rows * hidden];
    let mut gh = vec![0f32; rows * g3];
    for t in 0..steps {
        w_hh.matmul(&h, rows, &mut gh);
        for r in 0..rows {
            let row = r * steps + t;
            gate_row(
                &xw[row * g3..][..g3],
                &gh[r * g3..][..g3],
                bias,
                &h[r * hidden..][..hidden],
                &mut h_new[r * hidden..][..hidden],
            );
            out[row * hidden..][..hidden].copy_from_slice(&h_new[r * hidden..][..hidden]);
        }
        std::mem::swap(&mut h, &mut h_new);
    }
}

/// [`forward_rows`] with the rows split over the rayon threads.
pub(crate) fn forward_parallel(
    xw: &[f32],
    h0: Option<&[f32]>,
    steps: usize,
    w_hh: &PackedMatrix,
    bias: &Biases,
    out: &mut [f32],
) {
    let hidden = w_hh.k();
    let rows = out.len() / (steps * hidden).max(1);
    let part = rows_per_part(rows);
    out.par_chunks_mut(part * steps * hidden)
        .zip(xw.par_chunks(part * steps * 3 * hidden))
        .enumerate()
        .for_each(|(i, (out, xw))| {
            let h0 = h0.map(|h| {
                let n = out.len() / (steps * hidden);
                &h[i * part * hidden..][..n * hidden]
            });
            forward_rows(xw, h0, steps, w_hh, bias, out);
        });
}

/// What the backward pass of a block of rows reads.
#[derive(Clone, Copy)]
struct BackwardInputs<'a> {
    steps: usize,
    hidden: usize,
    xw: &'a [f32],
    gh: &'a [f32],
    prev: &'a [f32],
    d_out: &'a [f32],
    b_hh: &'a [f32],
    w_hh: &'a PackedMatrix,
}

/// Back-propagation through time for a block of rows: fills `d_xw` and `d_gh` (both
/// `(rows, steps, 3H)`).
fn backward_rows(inp: &BackwardInputs, d_xw: &mut [f32], d_gh: &mut [f32]) {
    Arch::new().dispatch(BackwardLoop { inp, d_xw, d_gh });
}

/// [`backward_rows`] as a `pulp` kernel (see [`ForwardLoop`]).
struct BackwardLoop<'a, 'b> {
    inp: &'b BackwardInputs<'a>,
    d_xw: &'b mut [f32],
    d_gh: &'b mut [f32],
}

impl WithSimd for BackwardLoop<'_, '_> {
    type Output = ();
    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        backward_rows_inner(self.inp, self.d_xw, self.d_gh);
    }
}

#[inline(always)]
fn backward_rows_inner(inp: &BackwardInputs, d_xw: &mut [f32], d_gh: &mut [f32]) {
    let (steps, hidden) = (inp.steps, inp.hidden);
    let g3 = 3 * hidden;
    let rows = d_xw.len() / (steps * g3).max(1);
    let mut carry = vec![0f32; rows * hidden];
    let mut direct = vec![0f32; rows * hidden];
    let mut step_dg = vec![0f32; rows * g3];
    let mut through_w = vec![0f32; rows * hidden];
    let b = inp.b_hh;
    for t in (0..steps).rev() {
        for r in 0..rows {
            let row = r * steps + t;
            let x = &inp.xw[row * g3..][..g3];
            let g = &inp.gh[row * g3..][..g3];
            let hp = &inp.prev[row * hidden..][..hidden];
            let dh_out = &inp.d_out[row * hidden..][..hidden];
            let dx = &mut d_xw[row * g3..][..g3];
            let dg = &mut step_dg[r * g3..][..g3];
            for j in 0..hidden {
                let dh = dh_out[j] + carry[r * hidden + j];
                let rg = sigmoid(x[j] + g[j] + b[j]);
                let z = sigmoid(x[hidden + j] + g[hidden + j] + b[hidden + j]);
                let ghn = g[2 * hidden + j] + b[2 * hidden + j];
                let n = tanh(x[2 * hidden + j] + rg * ghn);
                let dn = dh * (1.0 - z);
                let dz = dh * (hp[j] - n);
                let dan = dn * (1.0 - n * n);
                let dar = dan * ghn * rg * (1.0 - rg);
                let daz = dz * z * (1.0 - z);
                dx[j] = dar;
                dx[hidden + j] = daz;
                dx[2 * hidden + j] = dan;
                dg[j] = dar;
                dg[hidden + j] = daz;
                dg[2 * hidden + j] = dan * rg;
                direct[r * hidden + j] = dh * z;
            }
            d_gh[row * g3..][..g3].copy_from_slice(dg);
        }
        inp.w_hh.matmul(&step_dg, rows, &mut through_w);
        for ((c, d), w) in carry.iter_mut().zip(&direct).zip(&through_w) {
            *c = d + w;
        }
    }
}

impl GruRecurrence {
    fn check(&self, xw: usize, w_hh: usize, b_hh: usize) -> candle_core::Result<()> {
        let (t, b, h) = (self.steps, self.batch, self.hidden);
        if xw != t * b * 3 * h || w_hh != 3 * h * h || b_hh != 3 * h {
            bail!("gru recurrence: sizes {xw}, {w_hh}, {b_hh} do not match T={t}, B={b}, H={h}");
        }
        if let Some(h0) = &self.h0 {
            if h0.len() != b * h {
                bail!(
                    "gru recurrence: h0 has {} values, expected {}",
                    h0.len(),
                    b * h
                );
            }
        }
        Ok(())
    }

    /// Previous state of every step, `(B, T, H)`: `h0`, then the outputs of steps 0..T-1.
    fn previous_states(&self, outputs: &[f32]) -> Vec<f32> {
        let (steps, hidden) = (self.steps, self.hidden);
        let mut prev = vec![0f32; self.batch * steps * hidden];
        for b in 0..self.batch {
            let dst = &mut prev[b * steps * hidden..][..steps * hidden];
            if let Some(h0) = &self.h0 {
                dst[..hidden].copy_from_slice(&h0[b * hidden..][..hidden]);
            }
            dst[hidden..].copy_from_slice(&outputs[b * steps * hidden..][..(steps - 1) * hidden]);
        }
        prev
    }
}

impl CustomOp3 for GruRecurrence {
    fn name(&self) -> &'static str {
        "gru-recurrence"
    }

    fn cpu_fwd(
        &self,
        s1: &CpuStorage,
        l1: &Layout,
        s2: &CpuStorage,
        l2: &Layout,
        s3: &CpuStorage,
        l3: &Layout,
    ) -> candle_core::Result<(CpuStorage, Shape)> {
        let xw = f32_slice(s1, l1, "xw")?;
        let w_hh = f32_slice(s2, l2, "w_hh")?;
        let b_hh = f32_slice(s3, l3, "b_hh")?;
        self.check(xw.len(), w_hh.len(), b_hh.len())?;
        let (steps, batch, hidden) = (self.steps, self.batch, self.hidden);
        let packed = PackedMatrix::from_weight(w_hh, 3 * hidden, hidden);
        let bias = Biases::new(b_hh, None);
        let mut out = vec![0f32; batch * steps * hidden];
        forward_parallel(xw, self.h0.as_deref(), steps, &packed, &bias, &mut out);
        Ok((CpuStorage::F32(out), Shape::from((batch, steps, hidden))))
    }

    fn bwd(
        &self,
        xw: &Tensor,
        w_hh: &Tensor,
        b_hh: &Tensor,
        res: &Tensor,
        grad_res: &Tensor,
    ) -> candle_core::Result<(Option<Tensor>, Option<Tensor>, Option<Tensor>)> {
        let (steps, batch, hidden) = (self.steps, self.batch, self.hidden);
        let g3 = 3 * hidden;
        let device = xw.device().clone();
        let xw_v = xw.flatten_all()?.to_vec1::<f32>()?;
        let b_v = b_hh.flatten_all()?.to_vec1::<f32>()?;
        let out = res.flatten_all()?.to_vec1::<f32>()?;
        let d_out = grad_res.flatten_all()?.to_vec1::<f32>()?;
        self.check(xw_v.len(), w_hh.elem_count(), b_v.len())?;
        let w_cpu = w_hh.to_device(&Device::Cpu)?.contiguous()?;
        let w_v = w_cpu.flatten_all()?.to_vec1::<f32>()?;
        let prev = self.previous_states(&out);
        let rows = batch * steps;
        // Recompute W_hh h_{t-1} for every step with one matmul.
        let prev_t = Tensor::from_vec(prev, (rows, hidden), &Device::Cpu)?;
        let gh = prev_t
            .matmul(&w_cpu.t()?)?
            .flatten_all()?
            .to_vec1::<f32>()?;
        let prev = prev_t.flatten_all()?.to_vec1::<f32>()?;
        // d_gh (rows × 3H) · W_hh (3H × H) per step.
        let w_back = PackedMatrix::from_matrix(&w_v, g3, hidden);
        let inputs = BackwardInputs {
            steps,
            hidden,
            xw: &xw_v,
            gh: &gh,
            prev: &prev,
            d_out: &d_out,
            b_hh: &b_v,
            w_hh: &w_back,
        };
        let mut d_xw = vec![0f32; rows * g3];
        let mut d_gh = vec![0f32; rows * g3];
        let part = rows_per_part(batch) * steps * g3;
        d_xw.par_chunks_mut(part)
            .zip(d_gh.par_chunks_mut(part))
            .enumerate()
            .for_each(|(i, (dx, dg))| {
                let offset = i * part;
                let block = BackwardInputs {
                    xw: &inputs.xw[offset..][..dx.len()],
                    gh: &inputs.gh[offset..][..dx.len()],
                    prev: &inputs.prev[offset / 3..][..dx.len() / 3],
                    d_out: &inputs.d_out[offset / 3..][..dx.len() / 3],
                    ..inputs
                };
                backward_rows(&block, dx, dg);
            });
        let d_gh_t = Tensor::from_vec(d_gh, (rows, g3), &Device::Cpu)?;
        let d_w_hh = d_gh_t.t()?.matmul(&prev_t)?;
        let d_b_hh = d_gh_t.sum(0)?;
        let d_xw = Tensor::from_vec(d_xw, (batch, steps, g3), &Device::Cpu)?;
        Ok((
            Some(d_xw.to_device(&device)?),
            Some(d_w_hh.to_device(&device)?),
            Some(d_b_hh.to_device(&device)?),
        ))
    }
}
