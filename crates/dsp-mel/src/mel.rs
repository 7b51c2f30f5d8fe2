//! STFT power spectrum → mel spectrogram, planned once and reused.

use std::sync::Arc;

use ndarray::Array2;
use rayon::prelude::*;
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

use crate::config::MelConfig;
use crate::db::{power_to_db, DbConfig};
use crate::error::{DspError, Result};
use crate::filterbank::{mel_filterbank, sparse_bands, SparseBand};

/// Frames computed per parallel task (even: frames are transformed in pairs): big enough to
/// amortise the scratch buffers, small enough to balance two or more cores.
const FRAMES_PER_TASK: usize = 128;

/// A planned mel spectrogram: the FFT plan, window and filterbank are built once by
/// [`MelSpectrogram::new`] and reused by every [`MelSpectrogram::compute`].
///
/// ```
/// use dsp_mel::{MelConfig, MelSpectrogram};
/// let mel = MelSpectrogram::new(MelConfig::bowing())?;
/// let one_second = vec![0.0f32; 22_050];
/// let s = mel.compute(&one_second)?;
/// assert_eq!(s.dim(), (31, 128)); // 1 + len / hop frames (centred), 128 bands
/// # Ok::<(), dsp_mel::DspError>(())
/// ```
pub struct MelSpectrogram {
    cfg: MelConfig,
    hop: usize,
    window: Vec<f64>,
    bands: Vec<SparseBand>,
    /// Complex FFT of length `n_fft`; two real frames share one transform.
    fft: Arc<dyn Fft<f64>>,
}

impl std::fmt::Debug for MelSpectrogram {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MelSpectrogram")
            .field("cfg", &self.cfg)
            .finish_non_exhaustive()
    }
}

impl MelSpectrogram {
    /// Plans the FFT and builds the window and filterbank.
    pub fn new(cfg: MelConfig) -> Result<Self> {
        cfg.validate()?;
        let dense = mel_filterbank(&cfg)?;
        let bands = sparse_bands(&dense);
        let fft = FftPlanner::<f64>::new().plan_fft_forward(cfg.n_fft);
        Ok(Self {
            hop: cfg.hop_length(),
            window: cfg
                .window
                .coefficients(cfg.n_fft)
                .into_iter()
                .map(f64::from)
                .collect(),
            bands,
            fft,
            cfg,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &MelConfig {
        &self.cfg
    }

    /// Number of STFT frames for a signal of `len` samples (before pooling).
    pub fn n_stft_frames(&self, len: usize) -> usize {
        if self.cfg.center {
            1 + len / self.hop
        } else if len >= self.cfg.n_fft {
            1 + (len - self.cfg.n_fft) / self.hop
        } else {
            0
        }
    }

    /// Mel power spectrogram, shape `(frames, n_mels)`, frames in time order.
    ///
    /// Samples are assumed to be at `config().sample_rate_hz`. A signal shorter than `n_fft`
    /// still yields frames when `center` is on. Errors on empty or non-finite input, or on an
    /// uncentred signal shorter than one frame.
    pub fn compute(&self, samples: &[f32]) -> Result<Array2<f32>> {
        if samples.is_empty() {
            return Err(DspError::EmptyAudio);
        }
        if let Some(index) = first_non_finite(samples) {
            return Err(DspError::NonFiniteInput { index });
        }
        let n_frames = self.n_stft_frames(samples.len());
        if n_frames == 0 {
            return Err(DspError::TooShort {
                len: samples.len(),
                needed: self.cfg.n_fft - 1,
            });
        }
        let n_mels = self.cfg.n_mels;
        let mut out = vec![0.0f32; n_frames * n_mels];
        let pad = if self.cfg.center {
            self.cfg.n_fft / 2
        } else {
            0
        };
        out.par_chunks_mut(FRAMES_PER_TASK * n_mels)
            .enumerate()
            .for_each(|(task, chunk)| {
                let n_fft = self.cfg.n_fft;
                let zero = Complex::new(0.0, 0.0);
                let mut buf = vec![zero; n_fft];
                let mut scratch = vec![zero; self.fft.get_inplace_scratch_len()];
                let mut power_a = vec![0.0f32; n_fft / 2 + 1];
                let mut power_b = vec![0.0f32; n_fft / 2 + 1];
                let first = task * FRAMES_PER_TASK;
                let rows = chunk.len() / n_mels;
                let mut i = 0;
                while i < rows {
                    let pair = i + 1 < rows;
                    let start_a = (first + i) * self.hop;
                    let start_b = pair.then_some(start_a + self.hop);
                    self.fill_pair(samples, start_a, start_b, pad, &mut buf);
                    self.fft.process_with_scratch(&mut buf, &mut scratch);
                    self.split_power(&buf, &mut power_a, &mut power_b);
                    self.apply_bands(&power_a, &mut chunk[i * n_mels..(i + 1) * n_mels]);
                    if pair {
                        self.apply_bands(&power_b, &mut chunk[(i + 1) * n_mels..(i + 2) * n_mels]);
                    }
                    i += 2;
                }
            });
        let stft = Array2::from_shape_vec((n_frames, n_mels), out)
            .map_err(|e| DspError::InvalidConfig(e.to_string()))?;
        Ok(pool_frames(stft, self.cfg.pool_frames))
    }

    /// Mel spectrogram in dB (`power_to_db` with `db` applied over the whole array).
    pub fn compute_db(&self, samples: &[f32], db: &DbConfig) -> Result<Array2<f32>> {
        let mut s = self.compute(samples)?;
        if let Some(values) = s.as_slice_mut() {
            power_to_db(values, db);
        }
        Ok(s)
    }

    /// Packs the windowed frames starting at `start_a` and `start_b` (in the virtually padded
    /// signal) as real and imaginary parts of `buf`; a missing `b` frame is zeros.
    fn fill_pair(
        &self,
        samples: &[f32],
        start_a: usize,
        start_b: Option<usize>,
        pad: usize,
        buf: &mut [Complex<f64>],
    ) {
        let n_fft = buf.len();
        let interior = |start: usize| start >= pad && start - pad + n_fft <= samples.len();
        match start_b {
            Some(start_b) if interior(start_a) && interior(start_b) => {
                let a = &samples[start_a - pad..start_a - pad + n_fft];
                let b = &samples[start_b - pad..start_b - pad + n_fft];
                for (((z, xa), xb), w) in buf.iter_mut().zip(a).zip(b).zip(&self.window) {
                    *z = Complex::new(f64::from(*xa) * w, f64::from(*xb) * w);
                }
            }
            _ => {
                let at = |start: Option<usize>, j: usize| -> f64 {
                    match start {
                        Some(s) if s + j >= pad && s + j - pad < samples.len() => {
                            f64::from(samples[s + j - pad])
                        }
                        _ => 0.0,
                    }
                };
                for (j, (z, w)) in buf.iter_mut().zip(&self.window).enumerate() {
                    *z = Complex::new(at(Some(start_a), j) * w, at(start_b, j) * w);
                }
            }
        }
    }

    /// Separates the spectra of the two real frames packed as `a + i·b` and writes
    /// `|A|^power`, `|B|^power`, rounded to `f32` only at the end so faint bins keep their
    /// precision: `A[k] = (Z[k] + conj Z[N−k]) / 2`, `B[k] = (Z[k] − conj Z[N−k]) / 2i`.
    fn split_power(&self, z: &[Complex<f64>], power_a: &mut [f32], power_b: &mut [f32]) {
        let n = z.len();
        let half_power = f64::from(self.cfg.power) / 2.0;
        let scale = |x: f64| -> f32 {
            if half_power == 1.0 {
                x as f32
            } else {
                x.powf(half_power) as f32
            }
        };
        for (k, (pa, pb)) in power_a.iter_mut().zip(power_b.iter_mut()).enumerate() {
            let zk = z[k];
            let zc = if k == 0 { z[0].conj() } else { z[n - k].conj() };
            let (s, d) = (zk + zc, zk - zc);
            *pa = scale(0.25 * (s.re * s.re + s.im * s.im));
            *pb = scale(0.25 * (d.re * d.re + d.im * d.im));
        }
    }

    fn apply_bands(&self, power: &[f32], row: &mut [f32]) {
        for (value, band) in row.iter_mut().zip(&self.bands) {
            let bins = &power[band.start..band.start + band.weights.len()];
            *value = dot(bins, &band.weights);
        }
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

#[inline]
fn dot(a: &[f32], b: &[f32]) -> f32 {
    // Eight independent lanes over exact chunks: vectorises without reassociation flags.
    let mut acc = [0.0f32; 8];
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let (ra, rb) = (a8.remainder(), b8.remainder());
    for (x, y) in a8.zip(b8) {
        for k in 0..8 {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: f32 = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    acc.iter().sum::<f32>() + tail
}

/// Averages groups of `k` consecutive rows (the last group may be shorter).
///
/// ```
/// let a = ndarray::array![[1.0f32], [3.0], [5.0]];
/// assert_eq!(dsp_mel::pool_frames(a, 2), ndarray::array![[2.0f32], [5.0]]);
/// ```
pub fn pool_frames(frames: Array2<f32>, k: usize) -> Array2<f32> {
    if k <= 1 {
        return frames;
    }
    let (n, bands) = frames.dim();
    let out_n = n.div_ceil(k);
    let mut out = Array2::<f32>::zeros((out_n, bands));
    for (o, mut row) in out.rows_mut().into_iter().enumerate() {
        let group = frames.slice(ndarray::s![o * k..((o + 1) * k).min(n), ..]);
        let count = group.nrows() as f32;
        for g in group.rows() {
            row += &g;
        }
        row /= count;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Hop;

    #[test]
    fn short_signals_still_give_frames() {
        let mel = MelSpectrogram::new(MelConfig::bowing()).unwrap();
        let s = mel.compute(&[0.5; 10]).unwrap();
        assert_eq!(s.dim(), (1, 128));
        assert!(s.iter().all(|v| v.is_finite()));
    }

    #[test]
    fn bad_input_is_an_error() {
        let mel = MelSpectrogram::new(MelConfig::bowing()).unwrap();
        assert!(matches!(mel.compute(&[]), Err(DspError::EmptyAudio)));
        assert!(matches!(
            mel.compute(&[0.0, f32::NAN]),
            Err(DspError::NonFiniteInput { index: 1 })
        ));
        let uncentred = MelSpectrogram::new(MelConfig {
            center: false,
            ..MelConfig::default()
        })
        .unwrap();
        assert!(matches!(
            uncentred.compute(&[0.0; 100]),
            Err(DspError::TooShort { .. })
        ));
    }

    #[test]
    fn silence_is_zero_and_sine_peaks_in_the_right_band() {
        let cfg = MelConfig {
            hop: Hop::Samples(512),
            ..MelConfig::default()
        };
        let mel = MelSpectrogram::new(cfg.clone()).unwrap();
        assert!(mel.compute(&[0.0; 4096]).unwrap().iter().all(|&v| v == 0.0));
        let sr = cfg.sample_rate_hz as f32;
        let tone: Vec<f32> = (0..22_050)
            .map(|i| (2.0 * std::f32::consts::PI * 1000.0 * i as f32 / sr).sin())
            .collect();
        let s = mel.compute(&tone).unwrap();
        let row = s.row(20);
        let best = (0..row.len())
            .max_by(|&a, &b| row[a].total_cmp(&row[b]))
            .unwrap();
        let centres = crate::filterbank::mel_frequencies(130, 0.0, sr as f64 / 2.0, cfg.mel_scale);
        assert!((centres[best + 1] - 1000.0).abs() < 60.0, "band {best}");
    }

    #[test]
    fn pooling_averages() {
        let mel = MelSpectrogram::new(MelConfig::emotion()).unwrap();
        let s = mel.compute(&vec![0.1; 22_050 * 3]).unwrap();
        assert_eq!(s.dim(), (7, 64)); // 91 frames → ceil(91 / 15)
    }
}
