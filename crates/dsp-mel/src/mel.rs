//! Mel spectrogram: the workspace's STFT ([`crate::Stft`]) through a sparse mel filterbank,
//! planned once and reused.

use ndarray::Array2;

use crate::config::MelConfig;
use crate::db::{power_to_db, DbConfig};
use crate::error::{DspError, Result};
use crate::filterbank::{mel_filterbank, sparse_bands, SparseBand};
use crate::stft::{Stft, StftFloat};

/// A planned mel spectrogram: the FFT plan, window and filterbank are built once by
/// [`MelSpectrogram::new`] and reused by every [`MelSpectrogram::compute`].
///
/// The transform runs in `T`: `f64` by default ([`MelSpectrogram::new`], the networks'
/// features and the librosa parity figures), `f32` through
/// [`MelSpectrogram::with_precision`] (what librosa computes for `float32` audio).
///
/// ```
/// use dsp_mel::{MelConfig, MelSpectrogram};
/// let mel = MelSpectrogram::new(MelConfig::bowing())?;
/// let one_second = vec![0.0f32; 22_050];
/// let s = mel.compute(&one_second)?;
/// assert_eq!(s.dim(), (31, 128)); // 1 + len / hop frames (centred), 128 bands
/// let fast = MelSpectrogram::<f32>::with_precision(MelConfig::bowing())?;
/// assert_eq!(fast.compute(&one_second)?, s);
/// # Ok::<(), dsp_mel::DspError>(())
/// ```
pub struct MelSpectrogram<T: StftFloat = f64> {
    cfg: MelConfig,
    bands: Vec<SparseBand>,
    stft: Stft<T>,
}

impl<T: StftFloat> std::fmt::Debug for MelSpectrogram<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MelSpectrogram")
            .field("cfg", &self.cfg)
            .finish_non_exhaustive()
    }
}

impl MelSpectrogram<f64> {
    /// Plans the FFT (double precision) and builds the window and filterbank.
    pub fn new(cfg: MelConfig) -> Result<Self> {
        Self::with_precision(cfg)
    }
}

impl<T: StftFloat> MelSpectrogram<T> {
    /// Plans the FFT in precision `T` and builds the window and filterbank.
    pub fn with_precision(cfg: MelConfig) -> Result<Self> {
        cfg.validate()?;
        let dense = mel_filterbank(&cfg)?;
        let bands = sparse_bands(&dense);
        let stft = Stft::new(
            cfg.n_fft,
            cfg.hop_length(),
            cfg.window,
            cfg.center,
            cfg.power,
        )?;
        Ok(Self { cfg, bands, stft })
    }

    /// The configuration.
    pub fn config(&self) -> &MelConfig {
        &self.cfg
    }

    /// Number of STFT frames for a signal of `len` samples (before pooling).
    pub fn n_stft_frames(&self, len: usize) -> usize {
        self.stft.n_frames(len)
    }

    /// Mel power spectrogram, shape `(frames, n_mels)`, frames in time order.
    ///
    /// Samples are assumed to be at `config().sample_rate_hz`. A signal shorter than `n_fft`
    /// still yields frames when `center` is on. Errors on empty or non-finite input, or on an
    /// uncentred signal shorter than one frame.
    pub fn compute(&self, samples: &[f32]) -> Result<Array2<f32>> {
        let n_mels = self.cfg.n_mels;
        let out = self
            .stft
            .map_frames(samples, n_mels, |power, row| self.apply_bands(power, row))?;
        let stft = Array2::from_shape_vec((out.len() / n_mels, n_mels), out)
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

    fn apply_bands(&self, power: &[f32], row: &mut [f32]) {
        for (value, band) in row.iter_mut().zip(&self.bands) {
            let bins = &power[band.start..band.start + band.weights.len()];
            *value = dot(bins, &band.weights);
        }
    }
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
