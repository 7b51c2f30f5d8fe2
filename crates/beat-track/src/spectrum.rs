//! The log-mel spectrogram under the onset curve, in single precision.
//!
//! The same frames, window, filterbank (`dsp_mel::mel_filterbank`) and dB conversion
//! (`dsp_mel::power_to_db` semantics: `ref = 1`, `amin = 1e-10`, `top_db = 80` over the whole
//! spectrogram) as `librosa.feature.melspectrogram` + `power_to_db`, in float32 as librosa
//! itself computes for float32 audio. `dsp_mel::MelSpectrogram` keeps double precision for
//! the networks' features; here the onset curve only needs what librosa has. Frames are
//! transformed two at a time by one complex FFT ([`crate::pair_fft`]), which takes about
//! 40 % of the time of two real FFTs.

use dsp_mel::{mel_filterbank, Hop, MelConfig, Window};
use rayon::prelude::*;
use rustfft::num_complex::Complex;

use crate::error::Result;
use crate::pair_fft::PairFft;

/// Frames per parallel task (even: frames go through the FFT in pairs).
const FRAMES_PER_TASK: usize = 256;
/// librosa's `amin` and `top_db`.
const AMIN: f32 = 1e-10;
const TOP_DB: f32 = 80.0;

/// Width of the padded weight blocks.
const LANES: usize = 4;

/// One mel band: the first FFT bin it weights and the weights, zero-padded to a multiple of
/// [`LANES`] so every dot product runs in whole vector blocks (most bands are narrower than
/// one block; the power spectra carry [`LANES`] zero bins at the end for the overhang).
#[derive(Debug, Clone)]
struct Band {
    start: usize,
    weights: Vec<f32>,
}

/// A planned float32 log-mel spectrogram.
#[derive(Debug)]
pub(crate) struct LogMel {
    n_fft: usize,
    hop: usize,
    window: Vec<f32>,
    bands: Vec<Band>,
    fft: PairFft,
}

impl LogMel {
    pub fn new(sample_rate_hz: u32, n_fft: usize, hop: usize, n_mels: usize) -> Result<Self> {
        let cfg = MelConfig {
            sample_rate_hz,
            n_fft,
            hop: Hop::Samples(hop),
            n_mels,
            ..MelConfig::default()
        };
        cfg.validate()?;
        let dense = mel_filterbank(&cfg)?;
        let bands = dense
            .rows()
            .into_iter()
            .map(|row| {
                let start = row.iter().position(|&w| w != 0.0).unwrap_or(0);
                let end = row.iter().rposition(|&w| w != 0.0).map_or(start, |e| e + 1);
                let mut weights: Vec<f32> =
                    row.iter().skip(start).take(end - start).copied().collect();
                weights.resize((end - start).div_ceil(LANES) * LANES, 0.0);
                Band { start, weights }
            })
            .collect();
        Ok(Self {
            n_fft,
            hop,
            window: Window::Hann.coefficients(n_fft),
            bands,
            fft: PairFft::new(n_fft, false),
        })
    }

    pub fn n_mels(&self) -> usize {
        self.bands.len()
    }

    /// Whether the frame starting at `start` of the zero-padded signal (the signal begins at
    /// `n_fft / 2`) lies inside the signal.
    fn interior(&self, samples: &[f32], start: usize) -> bool {
        let pad = self.n_fft / 2;
        start >= pad && start - pad + self.n_fft <= samples.len()
    }

    /// Writes the windowed frame starting at `start` of the zero-padded signal (frame `t`
    /// starts at `t · hop`) through `put(i, value)`.
    fn frame(&self, samples: &[f32], start: usize, mut put: impl FnMut(usize, f32)) {
        let pad = self.n_fft / 2;
        for (i, w) in self.window.iter().enumerate() {
            let k = start + i;
            let x = if k >= pad && k - pad < samples.len() {
                samples[k - pad]
            } else {
                0.0
            };
            put(i, x * w);
        }
    }

    /// Packs the frames starting at `first` (real parts) and `first + hop` (imaginary parts;
    /// zeros when `pair` is false) into `data`.
    fn pack(&self, samples: &[f32], first: usize, pair: bool, data: &mut [Complex<f32>]) {
        let pad = self.n_fft / 2;
        let second = first + self.hop;
        if pair && self.interior(samples, first) && self.interior(samples, second) {
            let a = &samples[first - pad..first - pad + self.n_fft];
            let b = &samples[second - pad..second - pad + self.n_fft];
            for (((d, x), y), w) in data.iter_mut().zip(a).zip(b).zip(&self.window) {
                *d = Complex::new(x * w, y * w);
            }
            return;
        }
        self.frame(samples, first, |i, v| data[i] = Complex::new(v, 0.0));
        if pair {
            self.frame(samples, second, |i, v| data[i].im = v);
        }
    }

    /// Mel power in dB of one power spectrum (with [`LANES`] zero bins appended) into
    /// `row`; returns the row's maximum.
    fn mel_db(&self, power: &[f32], row: &mut [f32]) -> f32 {
        for (v, band) in row.iter_mut().zip(&self.bands) {
            *v = dot(
                &power[band.start..band.start + band.weights.len()],
                &band.weights,
            );
        }
        // Separate passes, so the branch-free `db` and the maximum vectorise over the bands.
        for v in row.iter_mut() {
            *v = db(*v);
        }
        let mut peak = [f32::NEG_INFINITY; LANES];
        let blocks = row.chunks_exact(LANES);
        let tail = blocks
            .remainder()
            .iter()
            .fold(f32::NEG_INFINITY, |m, &v| m.max(v));
        for c in blocks {
            for k in 0..LANES {
                peak[k] = if c[k] > peak[k] { c[k] } else { peak[k] };
            }
        }
        peak.iter().fold(tail, |m, &v| m.max(v))
    }

    /// dB mel spectrogram of centred, zero-padded frames: row-major `(1 + len / hop, n_mels)`.
    pub fn compute_db(&self, samples: &[f32]) -> Vec<f32> {
        let n_frames = 1 + samples.len() / self.hop;
        let n_mels = self.bands.len();
        let mut out = vec![0.0f32; n_frames * n_mels];
        let bins = self.n_fft / 2 + 1;
        // Power spectra with LANES zero bins after the last for the padded bands.
        let peaks: Vec<f32> = out
            .par_chunks_mut(FRAMES_PER_TASK * n_mels)
            .enumerate()
            .map(|(task, chunk)| {
                let mut buf = self.fft.buffers();
                let (mut power_a, mut power_b) =
                    (vec![0.0f32; bins + LANES], vec![0.0f32; bins + LANES]);
                let mut peak = f32::NEG_INFINITY;
                for (pair, rows) in chunk.chunks_mut(2 * n_mels).enumerate() {
                    let first = (task * FRAMES_PER_TASK + 2 * pair) * self.hop;
                    self.pack(samples, first, rows.len() > n_mels, &mut buf.data);
                    self.fft
                        .power_pair(&mut buf, &mut power_a[..bins], &mut power_b[..bins]);
                    let (row_a, row_b) = rows.split_at_mut(n_mels);
                    peak = peak.max(self.mel_db(&power_a, row_a));
                    if !row_b.is_empty() {
                        peak = peak.max(self.mel_db(&power_b, row_b));
                    }
                }
                peak
            })
            .collect();
        let floor = peaks.into_iter().fold(f32::NEG_INFINITY, f32::max) - TOP_DB;
        out.par_iter_mut().for_each(|v| *v = v.max(floor));
        out
    }
}

/// Dot product of two slices of a multiple of [`LANES`] values, in [`LANES`] independent
/// lanes (vectorises without reassociation flags).
#[inline]
fn dot(a: &[f32], b: &[f32]) -> f32 {
    let mut acc = [0.0f32; LANES];
    for (x, y) in a.chunks_exact(LANES).zip(b.chunks_exact(LANES)) {
        for k in 0..LANES {
            acc[k] += x[k] * y[k];
        }
    }
    acc.iter().sum()
}

/// `10 · log10(max(AMIN, power))` with a branch-free log2 (exponent bits plus a degree-8
/// polynomial of the mantissa, |error| < 1.1e-7 in log2, i.e. < 4e-7 dB), so the loop over
/// a frame's bands vectorises; `f32::log10` costs about a third of the spectrogram.
#[inline]
fn db(power: f32) -> f32 {
    const C: [f32; 8] = [
        1.442_688,
        -0.721_127_9,
        0.478_417_5,
        -0.346_390_96,
        0.240_180_77,
        -0.135_803_87,
        0.051_154_5,
        -0.009_118_109,
    ];
    const DB_PER_OCTAVE: f32 = 3.010_3; // 10 · log10(2) to f32 precision
    let x = power.max(AMIN);
    let bits = x.to_bits();
    let exponent = ((bits >> 23) & 0xff) as i32 - 127;
    let u = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000) - 1.0;
    let mut p = C[7];
    for c in C[..7].iter().rev() {
        p = p * u + c;
    }
    (exponent as f32 + u * p) * DB_PER_OCTAVE
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The spectrogram frame by frame with a real FFT in double precision.
    fn reference_db(mel: &LogMel, samples: &[f32]) -> Vec<f32> {
        let n = mel.n_fft;
        let fft = realfft::RealFftPlanner::<f64>::new().plan_fft_forward(n);
        let frames = 1 + samples.len() / mel.hop;
        let mut out = Vec::new();
        for t in 0..frames {
            let mut x = vec![0.0f64; n];
            mel.frame(samples, t * mel.hop, |i, v| x[i] = f64::from(v));
            let mut spec = fft.make_output_vec();
            fft.process(&mut x, &mut spec).unwrap();
            for band in &mel.bands {
                let end = (band.start + band.weights.len()).min(spec.len());
                let p: f64 = spec[band.start..end]
                    .iter()
                    .zip(&band.weights)
                    .map(|(z, &w)| z.norm_sqr() * f64::from(w))
                    .sum();
                out.push((10.0 * p.max(1e-10).log10()) as f32);
            }
        }
        let floor = out.iter().copied().fold(f32::NEG_INFINITY, f32::max) - TOP_DB;
        out.iter().map(|v| v.max(floor)).collect()
    }

    #[test]
    fn paired_frames_match_a_per_frame_real_fft() {
        let mel = LogMel::new(22_050, 512, 128, 40).unwrap();
        // An odd frame count (a lone last frame), a loud burst next to near-silence, and the
        // zero-padded edges.
        let samples: Vec<f32> = (0..128 * 40 + 37)
            .map(|i| {
                let t = i as f32 / 22_050.0;
                let burst = if (2000..2600).contains(&i) { 0.8 } else { 1e-3 };
                burst * (t * 440.0 * std::f32::consts::TAU).sin() + 1e-4 * ((i * 7919) % 13) as f32
            })
            .collect();
        let fast = mel.compute_db(&samples);
        let slow = reference_db(&mel, &samples);
        assert_eq!(fast.len(), slow.len());
        assert_eq!((1 + samples.len() / 128) % 2, 1);
        let worst = fast
            .iter()
            .zip(&slow)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        assert!(worst < 0.01, "largest difference {worst} dB");
    }

    #[test]
    fn fast_db_matches_log10() {
        for &x in &[
            1e-12f32, 1e-10, 3.7e-7, 0.01, 0.5, 1.0, 1.999, 2.0, 123.4, 5.6e6,
        ] {
            let exact = 10.0 * f64::from(x.max(AMIN)).log10();
            assert!(
                (f64::from(db(x)) - exact).abs() < 2e-5,
                "{x}: {} vs {exact}",
                db(x)
            );
        }
        let mut max_err = 0.0f64;
        for i in 0..100_000 {
            let x = 1e-10f32 * 1.000_3f32.powi(i);
            let exact = 10.0 * f64::from(x).log10();
            max_err = max_err.max((f64::from(db(x)) - exact).abs());
        }
        assert!(max_err < 2e-5, "{max_err}");
    }
}
