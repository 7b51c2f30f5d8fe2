//! A single-layer GRU over whole sequences, fast enough to train on a CPU.
//!
//! candle's [`candle_nn::rnn::GRU`] steps one frame at a time through ~15 graph nodes; this
//! layer does the input projection of all time steps as ONE `(T·B × in) @ (in × 3H)` matmul
//! (an ordinary candle op, so its gradient comes from candle's autograd) and the recurrence
//! as one custom op with a hand-written backward pass (`recurrence`), one `(B × H) @ (H × 3H)`
//! matmul per step. The parameters have candle's (and PyTorch's) names and shapes, so weights
//! are interchangeable with `candle_nn::rnn::gru`.

use candle_core::Tensor;
use candle_nn::{Init, VarBuilder};

use crate::error::{GruError, Result};
use crate::recurrence::GruRecurrence;

/// One GRU layer: `weight_ih_l0 (3H, in)`, `weight_hh_l0 (3H, H)`, `bias_ih_l0 (3H)`,
/// `bias_hh_l0 (3H)`, gates in `r, z, n` order.
///
/// ```
/// use candle_core::{DType, Device, Tensor};
/// use candle_nn::{VarBuilder, VarMap};
/// let vars = VarMap::new();
/// let vb = VarBuilder::from_varmap(&vars, DType::F32, &Device::Cpu);
/// let gru = gru_baseline::FusedGru::new(4, 8, vb)?;
/// let x = Tensor::zeros((2, 5, 4), DType::F32, &Device::Cpu)?; // (batch, time, in)
/// let h = gru.forward(&x, None)?;
/// assert_eq!(h.dims(), &[2, 5, 8]);
/// # Ok::<(), gru_baseline::GruError>(())
/// ```
#[derive(Debug, Clone)]
pub struct FusedGru {
    w_ih: Tensor,
    w_hh: Tensor,
    b_ih: Tensor,
    b_hh: Tensor,
    in_dim: usize,
    hidden: usize,
}

impl FusedGru {
    /// Fetches (or creates, with candle's GRU initialisation) the layer's parameters.
    pub fn new(in_dim: usize, hidden: usize, vb: VarBuilder) -> Result<Self> {
        if in_dim == 0 || hidden == 0 {
            return Err(GruError::Config(format!(
                "GRU sizes must be positive, got in {in_dim}, hidden {hidden}"
            )));
        }
        let kaiming = candle_nn::init::DEFAULT_KAIMING_UNIFORM;
        Ok(Self {
            w_ih: vb.get_with_hints((3 * hidden, in_dim), "weight_ih_l0", kaiming)?,
            w_hh: vb.get_with_hints((3 * hidden, hidden), "weight_hh_l0", kaiming)?,
            b_ih: vb.get_with_hints(3 * hidden, "bias_ih_l0", Init::Const(0.0))?,
            b_hh: vb.get_with_hints(3 * hidden, "bias_hh_l0", Init::Const(0.0))?,
            in_dim,
            hidden,
        })
    }

    /// Input size.
    pub fn in_dim(&self) -> usize {
        self.in_dim
    }

    /// Hidden (= output) size.
    pub fn hidden(&self) -> usize {
        self.hidden
    }

    /// Runs the layer over `x` `(B, T, in)` (batch-major, like candle's `rnn::RNN::seq`) from
    /// `h0` `(B, H)` (zeros when `None`; treated as a constant, as in truncated
    /// back-propagation through time) and returns every hidden state, `(B, T, H)`. The last
    /// one, [`FusedGru::last_state`], is the state to carry into the next chunk.
    pub fn forward(&self, x: &Tensor, h0: Option<&Tensor>) -> Result<Tensor> {
        let (batch, steps, in_dim) = x.dims3()?;
        if in_dim != self.in_dim {
            return Err(GruError::Shape {
                what: "GRU input".into(),
                expected: format!("(batch, time, {})", self.in_dim),
                got: format!("{:?}", x.dims()),
            });
        }
        if steps == 0 || batch == 0 {
            return Err(GruError::Empty("GRU input".into()));
        }
        let h = self.hidden;
        let xw = x
            .contiguous()?
            .reshape((batch * steps, in_dim))?
            .matmul(&self.w_ih.t()?)?
            .broadcast_add(&self.b_ih)?
            .reshape((batch, steps, 3 * h))?
            .contiguous()?;
        let h0 = match h0 {
            None => None,
            Some(s) => {
                if s.dims() != [batch, h] {
                    return Err(GruError::Shape {
                        what: "GRU initial state".into(),
                        expected: format!("({batch}, {h})"),
                        got: format!("{:?}", s.dims()),
                    });
                }
                Some(s.detach().flatten_all()?.to_vec1::<f32>()?)
            }
        };
        let op = GruRecurrence {
            steps,
            batch,
            hidden: h,
            h0,
        };
        let out = xw.apply_op3(&self.w_hh.contiguous()?, &self.b_hh.contiguous()?, op)?;
        Ok(out)
    }

    /// The last hidden state of an output of [`FusedGru::forward`], detached: `(B, H)`.
    pub fn last_state(out: &Tensor) -> Result<Tensor> {
        let steps = out.dim(1)?;
        Ok(out
            .narrow(1, steps - 1, 1)?
            .squeeze(1)?
            .detach()
            .contiguous()?)
    }

    /// The parameters, for optimizers and checks: `[w_ih, w_hh, b_ih, b_hh]`.
    pub fn parameters(&self) -> [&Tensor; 4] {
        [&self.w_ih, &self.w_hh, &self.b_ih, &self.b_hh]
    }

    /// Number of parameters.
    pub fn parameter_count(&self) -> usize {
        self.parameters().iter().map(|t| t.elem_count()).sum()
    }
}
