//! The log-mel spectrogram under the onset curve, in single precision.
//!
//! The same frames, window, filterbank (`dsp_mel::mel_filterbank`) and dB conversion
//! (`dsp_mel::power_to_db` semantics: `ref = 1`, `amin = 1e-10`, `top_db = 80` over the whole
//! spectrogram) as `librosa.feature.melspectrogram` + `power_to_db`, but with a float32 real
//! FFT as librosa itself computes for float32 audio. `dsp_mel::MelSpectrogram` keeps double
//! precision for the networks' features; here the onset curve only needs what librosa has,
//! and the float32 path is about twice as fast, which the beat tracker's budget needs.

use std::sync::Arc;

use dsp_mel::{mel_filterbank, Hop, MelConfig, Window};
use rayon::prelude::*;
use realfft::{RealFftPlanner, RealToComplex};

use crate::error::Result;

/// Frames per parallel task.
const FRAMES_PER_TASK: usize = 256;
/// librosa's `amin` and `top_db`.
const AMIN: f32 = 1e-10;
const TOP_DB: f32 = 80.0;

/// One mel band: the first FFT bin it weights and the weights.
#[derive(Debug, Clone)]
struct Band {
    start: usize,
    weights: Vec<f32>,
}

/// A planned float32 log-mel spectrogram.
pub(crate) struct LogMel {
    n_fft: usize,
    hop: usize,
    window: Vec<f32>,
    bands: Vec<Band>,
    fft: Arc<dyn RealToComplex<f32>>,
}

impl std::fmt::Debug for LogMel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LogMel")
            .field("n_fft", &self.n_fft)
            .field("hop", &self.hop)
            .field("n_mels", &self.bands.len())
            .finish_non_exhaustive()
    }
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
                Band {
                    start,
                    weights: row.iter().skip(start).take(end - start).copied().collect(),
                }
            })
            .collect();
        Ok(Self {
            n_fft,
            hop,
            window: Window::Hann.coefficients(n_fft),
            bands,
            fft: RealFftPlanner::<f32>::new().plan_fft_forward(n_fft),
        })
    }

    pub fn n_mels(&self) -> usize {
        self.bands.len()
    }

    /// dB mel spectrogram of centred, zero-padded frames: row-major `(1 + len / hop, n_mels)`.
    pub fn compute_db(&self, samples: &[f32]) -> Vec<f32> {
        let n_frames = 1 + samples.len() / self.hop;
        let n_mels = self.bands.len();
        let mut out = vec![0.0f32; n_frames * n_mels];
        let pad = self.n_fft / 2;
        let peaks: Vec<f32> = out
            .par_chunks_mut(FRAMES_PER_TASK * n_mels)
            .enumerate()
            .map(|(task, chunk)| {
                let mut time = self.fft.make_input_vec();
                let mut spec = self.fft.make_output_vec();
                let mut scratch = self.fft.make_scratch_vec();
                let mut power = vec![0.0f32; spec.len()];
                let mut peak = f32::NEG_INFINITY;
                for (i, row) in chunk.chunks_mut(n_mels).enumerate() {
                    let start = (task * FRAMES_PER_TASK + i) * self.hop;
                    // Frame covers padded[start .. start + n_fft] = samples[start − pad ..].
                    if start >= pad && start - pad + self.n_fft <= samples.len() {
                        let frame = &samples[start - pad..start - pad + self.n_fft];
                        for ((t, x), w) in time.iter_mut().zip(frame).zip(&self.window) {
                            *t = x * w;
                        }
                    } else {
                        for (j, (t, w)) in time.iter_mut().zip(&self.window).enumerate() {
                            let k = start + j;
                            *t = if k >= pad && k - pad < samples.len() {
                                samples[k - pad] * w
                            } else {
                                0.0
                            };
                        }
                    }
                    if self
                        .fft
                        .process_with_scratch(&mut time, &mut spec, &mut scratch)
                        .is_err()
                    {
                        continue;
                    }
                    for (p, z) in power.iter_mut().zip(&spec) {
                        *p = z.re * z.re + z.im * z.im;
                    }
                    for (v, band) in row.iter_mut().zip(&self.bands) {
                        let bins = &power[band.start..band.start + band.weights.len()];
                        *v = dot(bins, &band.weights);
                    }
                    for v in row.iter_mut() {
                        *v = db(*v);
                        peak = peak.max(*v);
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

/// Dot product in eight independent lanes (vectorises without reassociation flags).
#[inline]
fn dot(a: &[f32], b: &[f32]) -> f32 {
    let mut acc = [0.0f32; 8];
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: f32 = a8
        .remainder()
        .iter()
        .zip(b8.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in a8.zip(b8) {
        for k in 0..8 {
            acc[k] += x[k] * y[k];
        }
    }
    acc.iter().sum::<f32>() + tail
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
