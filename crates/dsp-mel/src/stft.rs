//! The short-time power spectrum of the workspace: centred (zero-padded) or plain frames,
//! a window, and two real frames per complex FFT, computed in `f32` or `f64`.
//!
//! Frames are packed in pairs as `a + i·b`; the spectra are separated after one complex
//! transform (see [`crate::fft::PairFft`]): `A[k] = (Z[k] + conj Z[N−k]) / 2`,
//! `B[k] = (Z[k] − conj Z[N−k]) / 2i`. The power `|X|^p` is rounded to `f32` only at the end.

use std::sync::Arc;

use rayon::prelude::*;
use rustfft::num_complex::Complex;
use rustfft::num_traits::Float;
use rustfft::{Fft, FftNum, FftPlanner};

use crate::config::Window;
use crate::error::{DspError, Result};

/// Frames computed per parallel task (even: frames are transformed in pairs): big enough to
/// amortise the scratch buffers, small enough to balance two or more cores.
const FRAMES_PER_TASK: usize = 128;

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// The precision an [`Stft`] (and a [`crate::MelSpectrogram`]) transforms in: `f64` (the
/// networks' features) or `f32` (what librosa computes for `float32` audio; twice the
/// values per SIMD register).
pub trait StftFloat: FftNum + Float + sealed::Sealed {
    /// Widens (or keeps) a sample.
    fn widen(x: f32) -> Self;
    /// Rounds to `f32`.
    fn narrow(self) -> f32;
}

impl StftFloat for f32 {
    #[inline]
    fn widen(x: f32) -> Self {
        x
    }
    #[inline]
    fn narrow(self) -> f32 {
        self
    }
}

impl StftFloat for f64 {
    #[inline]
    fn widen(x: f32) -> Self {
        f64::from(x)
    }
    #[inline]
    fn narrow(self) -> f32 {
        self as f32
    }
}

/// A planned STFT power spectrum: window and FFT plan built once by [`Stft::new`].
///
/// ```
/// use dsp_mel::{Stft, Window};
/// let stft = Stft::<f32>::new(512, 128, Window::Hann, true, 2.0)?;
/// let tone: Vec<f32> = (0..4096).map(|i| (i as f32 * 0.25).sin()).collect();
/// let power = stft.power(&tone)?; // (1 + 4096 / 128, 257)
/// assert_eq!(power.dim(), (33, 257));
/// let peak = (0..257).max_by(|&a, &b| power[[16, a]].total_cmp(&power[[16, b]])).unwrap();
/// assert_eq!(peak, 20); // 0.25 rad/sample · 512 / 2π ≈ bin 20.4
/// # Ok::<(), dsp_mel::DspError>(())
/// ```
pub struct Stft<T: StftFloat> {
    n_fft: usize,
    hop: usize,
    center: bool,
    power: f32,
    window: Vec<T>,
    /// Complex FFT of length `n_fft`; two real frames share one transform.
    fft: Arc<dyn Fft<T>>,
}

impl<T: StftFloat> std::fmt::Debug for Stft<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Stft")
            .field("n_fft", &self.n_fft)
            .field("hop", &self.hop)
            .field("center", &self.center)
            .field("power", &self.power)
            .finish_non_exhaustive()
    }
}

impl<T: StftFloat> Stft<T> {
    /// Plans frames of `n_fft` samples every `hop`, tapered by `window`, padded by `n_fft / 2`
    /// zeros on both sides when `center`, giving `|X|^power` per bin.
    pub fn new(n_fft: usize, hop: usize, window: Window, center: bool, power: f32) -> Result<Self> {
        if n_fft < 2 || hop == 0 || !(power.is_finite() && power > 0.0) {
            return Err(DspError::InvalidConfig(format!(
                "STFT needs n_fft ≥ 2 (got {n_fft}), hop ≥ 1 (got {hop}) and power > 0 (got {power})"
            )));
        }
        Ok(Self {
            n_fft,
            hop,
            center,
            power,
            window: window
                .coefficients(n_fft)
                .into_iter()
                .map(T::widen)
                .collect(),
            fft: FftPlanner::<T>::new().plan_fft_forward(n_fft),
        })
    }

    /// FFT length.
    pub fn n_fft(&self) -> usize {
        self.n_fft
    }

    /// Frequency bins per frame, `n_fft / 2 + 1`.
    pub fn n_bins(&self) -> usize {
        self.n_fft / 2 + 1
    }

    /// Number of frames for a signal of `len` samples.
    pub fn n_frames(&self, len: usize) -> usize {
        if self.center {
            1 + len / self.hop
        } else if len >= self.n_fft {
            1 + (len - self.n_fft) / self.hop
        } else {
            0
        }
    }

    /// Power spectrogram, shape `(frames, n_bins)`. Errors as [`Stft::map_frames`].
    pub fn power(&self, samples: &[f32]) -> Result<ndarray::Array2<f32>> {
        let bins = self.n_bins();
        let out = self.map_frames(samples, bins, |power, row| row.copy_from_slice(power))?;
        ndarray::Array2::from_shape_vec((out.len() / bins, bins), out)
            .map_err(|e| DspError::InvalidConfig(e.to_string()))
    }

    /// Runs `row(power, out)` on every frame's power spectrum (`n_bins` values) in parallel,
    /// each writing `width` values; returns the rows in time order, row-major.
    ///
    /// Errors on empty or non-finite input, or on an uncentred signal shorter than one frame.
    pub fn map_frames(
        &self,
        samples: &[f32],
        width: usize,
        row: impl Fn(&[f32], &mut [f32]) + Sync,
    ) -> Result<Vec<f32>> {
        if samples.is_empty() {
            return Err(DspError::EmptyAudio);
        }
        if let Some(index) = first_non_finite(samples) {
            return Err(DspError::NonFiniteInput { index });
        }
        let n_frames = self.n_frames(samples.len());
        if n_frames == 0 {
            return Err(DspError::TooShort {
                len: samples.len(),
                needed: self.n_fft - 1,
            });
        }
        let mut out = vec![0.0f32; n_frames * width];
        if width == 0 {
            return Ok(out);
        }
        let pad = if self.center { self.n_fft / 2 } else { 0 };
        out.par_chunks_mut(FRAMES_PER_TASK * width)
            .enumerate()
            .for_each(|(task, chunk)| {
                let zero = Complex::new(T::zero(), T::zero());
                let mut buf = vec![zero; self.n_fft];
                let mut scratch = vec![zero; self.fft.get_inplace_scratch_len()];
                let mut power_a = vec![0.0f32; self.n_bins()];
                let mut power_b = vec![0.0f32; self.n_bins()];
                let first = task * FRAMES_PER_TASK;
                let rows = chunk.len() / width;
                let mut i = 0;
                while i < rows {
                    let pair = i + 1 < rows;
                    let start_a = (first + i) * self.hop;
                    let start_b = pair.then_some(start_a + self.hop);
                    self.fill_pair(samples, start_a, start_b, pad, &mut buf);
                    self.fft.process_with_scratch(&mut buf, &mut scratch);
                    self.split_power(&buf, &mut power_a, &mut power_b);
                    row(&power_a, &mut chunk[i * width..(i + 1) * width]);
                    if pair {
                        row(&power_b, &mut chunk[(i + 1) * width..(i + 2) * width]);
                    }
                    i += 2;
                }
            });
        Ok(out)
    }

    /// Packs the windowed frames starting at `start_a` and `start_b` (in the virtually padded
    /// signal) as real and imaginary parts of `buf`; a missing `b` frame is zeros.
    fn fill_pair(
        &self,
        samples: &[f32],
        start_a: usize,
        start_b: Option<usize>,
        pad: usize,
        buf: &mut [Complex<T>],
    ) {
        let n_fft = buf.len();
        let interior = |start: usize| start >= pad && start - pad + n_fft <= samples.len();
        match start_b {
            Some(start_b) if interior(start_a) && interior(start_b) => {
                let a = &samples[start_a - pad..start_a - pad + n_fft];
                let b = &samples[start_b - pad..start_b - pad + n_fft];
                for (((z, &xa), &xb), &w) in buf.iter_mut().zip(a).zip(b).zip(&self.window) {
                    *z = Complex::new(T::widen(xa) * w, T::widen(xb) * w);
                }
            }
            _ => {
                let at = |start: Option<usize>, j: usize| -> T {
                    match start {
                        Some(s) if s + j >= pad && s + j - pad < samples.len() => {
                            T::widen(samples[s + j - pad])
                        }
                        _ => T::zero(),
                    }
                };
                for (j, (z, &w)) in buf.iter_mut().zip(&self.window).enumerate() {
                    *z = Complex::new(at(Some(start_a), j) * w, at(start_b, j) * w);
                }
            }
        }
    }

    /// Separates the spectra of the two real frames packed as `a + i·b` and writes
    /// `|A|^power`, `|B|^power`, rounded to `f32` only at the end so faint bins keep their
    /// precision.
    fn split_power(&self, z: &[Complex<T>], power_a: &mut [f32], power_b: &mut [f32]) {
        let two = T::one() + T::one();
        let half_power = T::widen(self.power) / two;
        // Two loops, not a branch per bin: with the branch inside, the compiler may compute
        // `powf` for every bin and select (measured: a third of the STFT's time).
        if half_power == T::one() {
            split_power_with(z, power_a, power_b, |x: T| x.narrow());
        } else {
            split_power_with(z, power_a, power_b, |x: T| x.powf(half_power).narrow());
        }
    }
}

/// `A[k] = (Z[k] + conj Z[N−k]) / 2`, `B[k] = (Z[k] − conj Z[N−k]) / 2i`, written as
/// `scale(|A[k]|²)` and `scale(|B[k]|²)`.
#[inline]
fn split_power_with<T: StftFloat>(
    z: &[Complex<T>],
    power_a: &mut [f32],
    power_b: &mut [f32],
    scale: impl Fn(T) -> f32,
) {
    let n = z.len();
    let two = T::one() + T::one();
    let quarter = T::one() / (two * two);
    for (k, (pa, pb)) in power_a.iter_mut().zip(power_b.iter_mut()).enumerate() {
        let zk = z[k];
        let zc = if k == 0 { z[0].conj() } else { z[n - k].conj() };
        let (s, d) = (zk + zc, zk - zc);
        *pa = scale(quarter * (s.re * s.re + s.im * s.im));
        *pb = scale(quarter * (d.re * d.re + d.im * d.im));
    }
}

/// Index of the first NaN or infinity; a branch-free scan per block so it vectorises.
pub(crate) fn first_non_finite(samples: &[f32]) -> Option<usize> {
    const BLOCK: usize = 4096;
    samples.chunks(BLOCK).enumerate().find_map(|(b, chunk)| {
        let all_finite = chunk.iter().fold(true, |ok, s| ok & s.is_finite());
        if all_finite {
            None
        } else {
            chunk
                .iter()
                .position(|s| !s.is_finite())
                .map(|i| b * BLOCK + i)
        }
    })
}
