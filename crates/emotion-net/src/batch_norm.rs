//! Batch normalisation over the last (channel) axis of an NHWC tensor, with running
//! statistics that a training pass updates and that can be re-estimated without dropout.

use std::sync::Mutex;

use candle_core::{Tensor, D};
use candle_nn::{Init, VarBuilder};

use crate::error::{EmotionError, Result};

/// How a forward pass treats batch norm.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BnPass {
    /// Normalise with the running statistics.
    Infer,
    /// Normalise with the batch's statistics and move the running ones towards them.
    Train,
    /// Normalise with the batch's statistics and add them to the calibration sums.
    Calibrate,
}

/// Sums of batch means and variances and their count, while calibrating.
type CalibrationSums = Option<(Tensor, Tensor, usize)>;

/// Batch normalisation over the last (channel) axis, with running statistics that a
/// training forward pass updates.
#[derive(Debug)]
pub struct BatchNormNhwc {
    gamma: Tensor,
    beta: Tensor,
    running_mean: Mutex<Tensor>,
    running_var: Mutex<Tensor>,
    eps: f64,
    momentum: f64,
    name: String,
    calibration: Mutex<CalibrationSums>,
}

impl BatchNormNhwc {
    pub(crate) fn new(
        channels: usize,
        eps: f64,
        momentum: f64,
        vb: VarBuilder,
        name: &str,
    ) -> Result<Self> {
        Ok(Self {
            gamma: vb.get_with_hints(channels, "gamma", Init::Const(1.0))?,
            beta: vb.get_with_hints(channels, "beta", Init::Const(0.0))?,
            running_mean: Mutex::new(vb.get_with_hints(
                channels,
                "running_mean",
                Init::Const(0.0),
            )?),
            running_var: Mutex::new(vb.get_with_hints(
                channels,
                "running_var",
                Init::Const(1.0),
            )?),
            eps,
            momentum,
            name: name.to_string(),
            calibration: Mutex::new(None),
        })
    }

    /// Per-channel mean and (biased) variance of a batch.
    fn batch_statistics(x: &Tensor) -> Result<(Tensor, Tensor)> {
        let c = x.dim(D::Minus1)?;
        // Column means as a matrix product: candle's reductions over a leading axis
        // are slow on the CPU.
        let flat = x.reshape(((), c))?;
        let n = flat.dim(0)?;
        let ones = Tensor::ones((1, n), flat.dtype(), flat.device())?;
        let mean = (ones.matmul(&flat)? / n as f64)?.squeeze(0)?;
        let centred = flat.broadcast_sub(&mean)?;
        let var = (ones.matmul(&centred.sqr()?)? / n as f64)?.squeeze(0)?;
        Ok((mean, var))
    }

    fn poisoned() -> crate::EmotionError {
        EmotionError::Config("batch-norm statistics poisoned".into())
    }

    pub(crate) fn forward(&self, x: &Tensor, pass: BnPass) -> Result<Tensor> {
        let (mean, var) = match pass {
            BnPass::Train => {
                let (mean, var) = Self::batch_statistics(x)?;
                let m = self.momentum;
                let mut rm = self.running_mean.lock().map_err(|_| Self::poisoned())?;
                let mut rv = self.running_var.lock().map_err(|_| Self::poisoned())?;
                *rm = ((rm.detach() * m)? + (mean.detach() * (1.0 - m))?)?;
                *rv = ((rv.detach() * m)? + (var.detach() * (1.0 - m))?)?;
                (mean, var)
            }
            BnPass::Calibrate => {
                let (mean, var) = Self::batch_statistics(&x.detach())?;
                let mut sums = self.calibration.lock().map_err(|_| Self::poisoned())?;
                *sums = Some(match sums.take() {
                    Some((sm, sv, k)) => ((sm + &mean)?, (sv + &var)?, k + 1),
                    None => (mean.clone(), var.clone(), 1),
                });
                (mean, var)
            }
            BnPass::Infer => {
                let rm = self.running_mean.lock().map_err(|_| Self::poisoned())?;
                let rv = self.running_var.lock().map_err(|_| Self::poisoned())?;
                (rm.clone(), rv.clone())
            }
        };
        let inv = (var + self.eps)?.sqrt()?.recip()?;
        Ok(x.broadcast_sub(&mean)?
            .broadcast_mul(&(inv * &self.gamma)?)?
            .broadcast_add(&self.beta)?)
    }

    /// Clears the calibration sums (see [`BnPass::Calibrate`]).
    pub(crate) fn start_calibration(&self) {
        if let Ok(mut sums) = self.calibration.lock() {
            *sums = None;
        }
    }

    /// Replaces the running statistics by the averages of the calibration batches (if any).
    pub(crate) fn finish_calibration(&self) -> Result<()> {
        let sums = self
            .calibration
            .lock()
            .map_err(|_| Self::poisoned())?
            .take();
        if let Some((sm, sv, k)) = sums {
            *self.running_mean.lock().map_err(|_| Self::poisoned())? = (sm / k as f64)?;
            *self.running_var.lock().map_err(|_| Self::poisoned())? = (sv / k as f64)?;
        }
        Ok(())
    }

    /// The running statistics as `(name, tensor)` pairs (`bnK.running_mean`, `…var`).
    pub fn running_stats(&self) -> Vec<(String, Tensor)> {
        let mut out = Vec::new();
        if let Ok(m) = self.running_mean.lock() {
            out.push((format!("{}.running_mean", self.name), m.clone()));
        }
        if let Ok(v) = self.running_var.lock() {
            out.push((format!("{}.running_var", self.name), v.clone()));
        }
        out
    }
}
