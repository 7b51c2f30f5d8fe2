//! FFT plans for the whole workspace: `dsp-mel` is the only crate that plans transforms.
//!
//! Plan once, keep the `Arc`, and let every caller own its buffers (as `rustfft` and
//! `realfft` do): [`plan_forward`] / [`plan_inverse`] give complex transforms,
//! [`plan_real_forward`] / [`plan_real_inverse`] real-input ones, and [`Planner`] keeps both
//! planners when several lengths are planned together (plans of one length share twiddles).
//! [`PairFft`] transforms two real frames with one complex FFT (power spectra or
//! autocorrelations of both).
//!
//! ```
//! use dsp_mel::fft::{plan_real_forward, Complex};
//! let fft = plan_real_forward::<f32>(8);
//! let mut x = vec![1.0f32; 8];
//! let mut spectrum = fft.make_output_vec();
//! fft.process(&mut x, &mut spectrum).expect("buffers of the planned lengths");
//! assert_eq!(spectrum[0], Complex::new(8.0, 0.0));
//! ```

use std::sync::Arc;

use realfft::RealFftPlanner;
use rustfft::FftPlanner;

pub use realfft::{ComplexToReal, RealToComplex};
pub use rustfft::num_complex::Complex;
pub use rustfft::{Fft, FftNum};

pub use crate::pair_fft::{PairBuffers, PairFft};

/// The smallest even length ≥ `n` whose only prime factors are 2, 3 and 5: a fast FFT
/// size for zero-padded transforms such as autocorrelations.
///
/// ```
/// use dsp_mel::fft::smooth_even_at_least;
/// assert_eq!(smooth_even_at_least(2169), 2250); // 2 · 3² · 5³
/// assert_eq!(smooth_even_at_least(2048), 2048);
/// assert_eq!(smooth_even_at_least(0), 2);
/// ```
pub fn smooth_even_at_least(n: usize) -> usize {
    let mut m = n.max(2) + n % 2;
    loop {
        let mut r = m;
        for p in [2, 3, 5] {
            while r.is_multiple_of(p) {
                r /= p;
            }
        }
        if r == 1 {
            return m;
        }
        m += 2;
    }
}

/// Complex and real-input FFT planners of one precision (`f32` or `f64`).
pub struct Planner<T: FftNum> {
    complex: FftPlanner<T>,
    real: RealFftPlanner<T>,
}

impl<T: FftNum> std::fmt::Debug for Planner<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Planner").finish_non_exhaustive()
    }
}

impl<T: FftNum> Default for Planner<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: FftNum> Planner<T> {
    /// Empty planners.
    pub fn new() -> Self {
        Self {
            complex: FftPlanner::new(),
            real: RealFftPlanner::new(),
        }
    }

    /// A forward complex FFT of `len` points (unnormalised).
    pub fn forward(&mut self, len: usize) -> Arc<dyn Fft<T>> {
        self.complex.plan_fft_forward(len)
    }

    /// An inverse complex FFT of `len` points (unnormalised: forward then inverse scales by
    /// `len`).
    pub fn inverse(&mut self, len: usize) -> Arc<dyn Fft<T>> {
        self.complex.plan_fft_inverse(len)
    }

    /// A forward FFT of `len` real samples to `len / 2 + 1` complex bins.
    pub fn real_forward(&mut self, len: usize) -> Arc<dyn RealToComplex<T>> {
        self.real.plan_fft_forward(len)
    }

    /// The inverse of [`Planner::real_forward`] (unnormalised).
    pub fn real_inverse(&mut self, len: usize) -> Arc<dyn ComplexToReal<T>> {
        self.real.plan_fft_inverse(len)
    }
}

/// A forward complex FFT of `len` points.
pub fn plan_forward<T: FftNum>(len: usize) -> Arc<dyn Fft<T>> {
    Planner::new().forward(len)
}

/// An inverse complex FFT of `len` points (unnormalised).
pub fn plan_inverse<T: FftNum>(len: usize) -> Arc<dyn Fft<T>> {
    Planner::new().inverse(len)
}

/// A forward FFT of `len` real samples.
pub fn plan_real_forward<T: FftNum>(len: usize) -> Arc<dyn RealToComplex<T>> {
    Planner::new().real_forward(len)
}

/// An inverse FFT to `len` real samples (unnormalised).
pub fn plan_real_inverse<T: FftNum>(len: usize) -> Arc<dyn ComplexToReal<T>> {
    Planner::new().real_inverse(len)
}
