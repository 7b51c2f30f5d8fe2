//! Dropout whose masks come from a seeded generator (candle's CPU random numbers cannot be
//! seeded, and `candle_nn::ops::dropout` always drops).

use std::sync::{Arc, Mutex};

use crate::rng::Rng;
use candle_core::{Tensor, D};

/// A seeded random stream shared by all dropout layers of one network.
#[derive(Debug, Clone)]
pub struct DropoutRng(Arc<Mutex<Rng>>);

impl DropoutRng {
    /// A stream for `seed`.
    pub fn new(seed: u64) -> Self {
        Self(Arc::new(Mutex::new(Rng::new(seed))))
    }

    /// Restarts the stream from `seed` (e.g. at the start of each epoch).
    pub fn reseed(&self, seed: u64) {
        if let Ok(mut rng) = self.0.lock() {
            *rng = Rng::new(seed);
        }
    }

    fn mask(&self, n: usize, drop_p: f32) -> Vec<f32> {
        let keep = 1.0 - drop_p;
        let scale = 1.0 / keep;
        // Compare 24 random bits against the keep probability.
        let threshold = (f64::from(keep) * f64::from(1u32 << 24)) as u64;
        match self.0.lock() {
            Ok(mut rng) => (0..n)
                .map(|_| {
                    if (rng.next_u64() >> 40) < threshold {
                        scale
                    } else {
                        0.0
                    }
                })
                .collect(),
            Err(_) => vec![1.0; n],
        }
    }
}

/// Inverted dropout: in training, zeroes each value with probability `p` and scales the rest
/// by `1/(1−p)`; the identity otherwise.
#[derive(Debug, Clone)]
pub struct SeededDropout {
    p: f32,
    rng: DropoutRng,
}

impl SeededDropout {
    /// A layer dropping with probability `p` (0 ≤ p < 1), drawing from `rng`.
    pub fn new(p: f32, rng: DropoutRng) -> Self {
        Self {
            p: p.clamp(0.0, 0.999),
            rng,
        }
    }

    /// The drop probability.
    pub fn p(&self) -> f32 {
        self.p
    }

    /// Applies the layer (`train` = true drops).
    ///
    /// ```
    /// use net_core::nn::{DropoutRng, SeededDropout};
    /// let x = candle_core::Tensor::ones(1000, candle_core::DType::F32, &candle_core::Device::Cpu)?;
    /// let d = SeededDropout::new(0.5, DropoutRng::new(1));
    /// assert_eq!(d.forward_t(&x, false)?.sum_all()?.to_scalar::<f32>()?, 1000.0);
    /// let kept = d.forward_t(&x, true)?.sum_all()?.to_scalar::<f32>()? / 2.0;
    /// assert!((400.0..600.0).contains(&kept));
    /// # Ok::<(), candle_core::Error>(())
    /// ```
    pub fn forward_t(&self, x: &Tensor, train: bool) -> candle_core::Result<Tensor> {
        if !train || self.p == 0.0 {
            return Ok(x.clone());
        }
        let mask = Tensor::from_vec(self.rng.mask(x.elem_count(), self.p), x.shape(), x.device())?;
        x.mul(&mask)
    }

    /// Like [`SeededDropout::forward_t`] but one mask value per feature vector (the last
    /// dimension is dropped as a whole), e.g. for dropout shared across time.
    pub fn forward_t_last_dim_shared(
        &self,
        x: &Tensor,
        train: bool,
    ) -> candle_core::Result<Tensor> {
        if !train || self.p == 0.0 {
            return Ok(x.clone());
        }
        let last = x.dim(D::Minus1)?;
        let mut shape = x.dims().to_vec();
        if let Some(l) = shape.last_mut() {
            *l = 1;
        }
        let n = x.elem_count() / last.max(1);
        let mask = Tensor::from_vec(self.rng.mask(n, self.p), shape, x.device())?;
        x.broadcast_mul(&mask)
    }
}
