//! The GRU recurrence over all time steps as ONE candle custom op, with a hand-written
//! backward pass (back-propagation through time).
//!
//! Built from candle's ordinary ops, a GRU unrolled over `T` steps makes ~15 graph nodes
//! per step and layer; candle's backward of each per-step slice of the input projection
//! allocates and adds a tensor as large as the whole sequence (O(T²) work), and its graph
//! walk recurses once per node. This op keeps the graph at one node per layer: the forward
//! runs the loop on plain slices (one `(B × H) @ (H × 3H)` matmul per step), the backward
//! recomputes the gates with one `(T·B × H) @ (H × 3H)` matmul, walks back in time with one
//! `(B × 3H) @ (3H × H)` matmul per step, and gets `∂L/∂W_hh` with one final matmul.
//!
//! Gates follow PyTorch / candle (`r, z, n` order, `b_hh` inside the reset product):
//! `r = σ(x_r + W_hr h + b_hr)`, `z = σ(x_z + W_hz h + b_hz)`,
//! `n = tanh(x_n + r ⊙ (W_hn h + b_hn))`, `h' = (1 − z) ⊙ n + z ⊙ h`, where `x = W_ih x_t + b_ih`
//! is computed for all steps beforehand (see [`crate::FusedGru`]).

use candle_core::{bail, CpuStorage, CustomOp3, Device, Layout, Shape, Tensor};

use crate::kernels::{matmul_bt, SMALL_BATCH_ROWS};

/// The recurrence of one GRU layer: inputs `xw` `(T, B, 3H)` (input projection incl. `b_ih`),
/// `w_hh` `(3H, H)`, `b_hh` `(3H)`; output all hidden states `(T, B, H)`.
pub(crate) struct GruRecurrence {
    pub steps: usize,
    pub batch: usize,
    pub hidden: usize,
    /// Initial state `(B, H)`, row-major; `None` = zeros. Treated as a constant (detached).
    pub h0: Option<Vec<f32>>,
}

fn sigmoid(x: f32) -> f32 {
    1.0 / (1.0 + (-x).exp())
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

/// `a (rows × k) @ w (k × n)` where `w` is given as a candle tensor (possibly transposed).
fn matmul_into(a: &[f32], rows: usize, k: usize, w: &Tensor) -> candle_core::Result<Vec<f32>> {
    let a = Tensor::from_slice(a, (rows, k), &Device::Cpu)?;
    a.matmul(w)?.flatten_all()?.to_vec1::<f32>()
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

    /// Previous state of every step, `(T·B, H)`: `h0`, then the outputs of steps 0..T-1.
    fn previous_states(&self, outputs: &[f32]) -> Vec<f32> {
        let bh = self.batch * self.hidden;
        let mut prev = Vec::with_capacity(self.steps * bh);
        match &self.h0 {
            Some(h0) => prev.extend_from_slice(h0),
            None => prev.resize(bh, 0.0),
        }
        prev.extend_from_slice(&outputs[..(self.steps - 1) * bh]);
        prev
    }
}

impl GruRecurrence {
    /// New states `h_new` `(B, H)` from one step's input projection `x` `(B, 3H)`, recurrent
    /// product `gh` `(B, 3H)` (without `b_hh`) and previous states `h_prev`.
    fn gates(&self, x: &[f32], gh: &[f32], b_hh: &[f32], h_prev: &[f32], h_new: &mut [f32]) {
        let (hidden, g3) = (self.hidden, 3 * self.hidden);
        for b in 0..self.batch {
            let x = &x[b * g3..][..g3];
            let g = &gh[b * g3..][..g3];
            let hp = &h_prev[b * hidden..][..hidden];
            let o = &mut h_new[b * hidden..][..hidden];
            for j in 0..hidden {
                let r = sigmoid(x[j] + g[j] + b_hh[j]);
                let z = sigmoid(x[hidden + j] + g[hidden + j] + b_hh[hidden + j]);
                let n = (x[2 * hidden + j] + r * (g[2 * hidden + j] + b_hh[2 * hidden + j])).tanh();
                o[j] = (1.0 - z) * n + z * hp[j];
            }
        }
    }

    /// The forward loop for one or two rows (inference): the recurrent product by
    /// [`matmul_bt`] instead of candle's gemm.
    fn forward_small_batch(&self, xw: &[f32], w_hh: &[f32], b_hh: &[f32]) -> Vec<f32> {
        let (steps, batch, hidden) = (self.steps, self.batch, self.hidden);
        let (g3, bh) = (3 * hidden, batch * hidden);
        let mut out = vec![0f32; steps * bh];
        let zeros = vec![0f32; bh];
        let mut gh = vec![0f32; batch * g3];
        for t in 0..steps {
            let (done, rest) = out.split_at_mut(t * bh);
            let h_prev: &[f32] = if t == 0 {
                self.h0.as_deref().unwrap_or(&zeros)
            } else {
                &done[(t - 1) * bh..]
            };
            matmul_bt(h_prev, batch, hidden, w_hh, g3, &mut gh);
            self.gates(
                &xw[t * batch * g3..][..batch * g3],
                &gh,
                b_hh,
                h_prev,
                &mut rest[..bh],
            );
        }
        out
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
        if batch <= SMALL_BATCH_ROWS {
            let out = self.forward_small_batch(xw, w_hh, b_hh);
            return Ok((CpuStorage::F32(out), Shape::from((steps, batch, hidden))));
        }
        let g3 = 3 * hidden;
        // (H × 3H) view of W_hhᵀ, built once.
        let w_t = Tensor::from_slice(w_hh, (g3, hidden), &Device::Cpu)?.t()?;
        let bh = batch * hidden;
        let mut out = vec![0f32; steps * bh];
        let zeros = vec![0f32; bh];
        for t in 0..steps {
            let (done, rest) = out.split_at_mut(t * bh);
            let h_prev: &[f32] = if t == 0 {
                self.h0.as_deref().unwrap_or(&zeros)
            } else {
                &done[(t - 1) * bh..]
            };
            let gh = matmul_into(h_prev, batch, hidden, &w_t)?;
            self.gates(
                &xw[t * batch * g3..][..batch * g3],
                &gh,
                b_hh,
                h_prev,
                &mut rest[..bh],
            );
        }
        Ok((CpuStorage::F32(out), Shape::from((steps, batch, hidden))))
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
        let (g3, bh) = (3 * hidden, batch * hidden);
        let device = xw.device().clone();
        let xw_v = xw.flatten_all()?.to_vec1::<f32>()?;
        let b_v = b_hh.flatten_all()?.to_vec1::<f32>()?;
        let out = res.flatten_all()?.to_vec1::<f32>()?;
        let d_out = grad_res.flatten_all()?.to_vec1::<f32>()?;
        self.check(xw_v.len(), w_hh.elem_count(), b_v.len())?;
        let w_cpu = w_hh.to_device(&Device::Cpu)?.contiguous()?;
        let prev = self.previous_states(&out);
        // Recompute W_hh h_{t-1} for every step with one matmul.
        let gh = matmul_into(&prev, steps * batch, hidden, &w_cpu.t()?)?;

        let mut d_xw = vec![0f32; steps * batch * g3];
        let mut d_gh = vec![0f32; steps * batch * g3];
        let mut carry = vec![0f32; bh];
        let mut direct = vec![0f32; bh];
        for t in (0..steps).rev() {
            for b in 0..batch {
                let row = t * batch + b;
                let x = &xw_v[row * g3..][..g3];
                let g = &gh[row * g3..][..g3];
                let hp = &prev[row * hidden..][..hidden];
                let dh_out = &d_out[row * hidden..][..hidden];
                let dx = &mut d_xw[row * g3..][..g3];
                let dg = &mut d_gh[row * g3..][..g3];
                for j in 0..hidden {
                    let dh = dh_out[j] + carry[b * hidden + j];
                    let r = sigmoid(x[j] + g[j] + b_v[j]);
                    let z = sigmoid(x[hidden + j] + g[hidden + j] + b_v[hidden + j]);
                    let ghn = g[2 * hidden + j] + b_v[2 * hidden + j];
                    let n = (x[2 * hidden + j] + r * ghn).tanh();
                    let dn = dh * (1.0 - z);
                    let dz = dh * (hp[j] - n);
                    let dan = dn * (1.0 - n * n);
                    let dar = dan * ghn * r * (1.0 - r);
                    let daz = dz * z * (1.0 - z);
                    dx[j] = dar;
                    dx[hidden + j] = daz;
                    dx[2 * hidden + j] = dan;
                    dg[j] = dar;
                    dg[hidden + j] = daz;
                    dg[2 * hidden + j] = dan * r;
                    direct[b * hidden + j] = dh * z;
                }
            }
            let through_w = matmul_into(&d_gh[t * batch * g3..][..batch * g3], batch, g3, &w_cpu)?;
            for ((c, d), w) in carry.iter_mut().zip(&direct).zip(&through_w) {
                *c = d + w;
            }
        }
        let rows = steps * batch;
        let d_gh_t = Tensor::from_vec(d_gh, (rows, g3), &Device::Cpu)?;
        let prev_t = Tensor::from_vec(prev, (rows, hidden), &Device::Cpu)?;
        let d_w_hh = d_gh_t.t()?.matmul(&prev_t)?;
        let d_b_hh = d_gh_t.sum(0)?;
        let d_xw = Tensor::from_vec(d_xw, (steps, batch, g3), &Device::Cpu)?;
        Ok((
            Some(d_xw.to_device(&device)?),
            Some(d_w_hh.to_device(&device)?),
            Some(d_b_hh.to_device(&device)?),
        ))
    }
}
