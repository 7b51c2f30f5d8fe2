//! The log-mel spectrogram under the onset curve: `dsp_mel::MelSpectrogram` (librosa's
//! frames, Hann window, Slaney filterbank; the workspace's one STFT) in single precision, as
//! librosa itself computes for float32 audio, then `power_to_db` with `ref = 1`,
//! `amin = 1e-10`, `top_db = 80` over the whole spectrogram, through a branch-free `log10`.

use dsp_mel::{Hop, MelConfig, MelSpectrogram};
use rayon::prelude::*;

use crate::error::Result;

/// librosa's `amin` and `top_db`.
const AMIN: f32 = 1e-10;
const TOP_DB: f32 = 80.0;

/// Bands per block of the maximum search (vectorises).
const LANES: usize = 4;

/// A planned float32 log-mel spectrogram.
#[derive(Debug)]
pub(crate) struct LogMel {
    mel: MelSpectrogram<f32>,
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
        Ok(Self {
            mel: MelSpectrogram::with_precision(cfg)?,
        })
    }

    pub fn n_mels(&self) -> usize {
        self.mel.config().n_mels
    }

    /// dB mel spectrogram of centred, zero-padded frames: row-major `(1 + len / hop, n_mels)`.
    /// The samples must be non-empty and finite (checked by the caller).
    pub fn compute_db(&self, samples: &[f32]) -> Result<Vec<f32>> {
        let power = self.mel.compute(samples)?;
        let mut out = power.into_raw_vec_and_offset().0;
        let n_mels = self.n_mels().max(1);
        let peak = out
            .par_chunks_mut(n_mels * 64)
            .map(|rows| {
                // Separate passes, so the branch-free `db` and the maximum vectorise.
                for v in rows.iter_mut() {
                    *v = db(*v);
                }
                block_max(rows)
            })
            .reduce(|| f32::NEG_INFINITY, f32::max);
        let floor = peak - TOP_DB;
        out.par_iter_mut().for_each(|v| *v = v.max(floor));
        Ok(out)
    }
}

/// The maximum of `x`, in [`LANES`] independent lanes.
fn block_max(x: &[f32]) -> f32 {
    let mut peak = [f32::NEG_INFINITY; LANES];
    let blocks = x.chunks_exact(LANES);
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

    /// The spectrogram frame by frame with a real FFT in double precision and a dense
    /// filterbank.
    fn reference_db(sr: u32, n: usize, hop: usize, n_mels: usize, samples: &[f32]) -> Vec<f32> {
        let cfg = MelConfig {
            sample_rate_hz: sr,
            n_fft: n,
            hop: Hop::Samples(hop),
            n_mels,
            ..MelConfig::default()
        };
        let bank = dsp_mel::mel_filterbank(&cfg).unwrap();
        let window = dsp_mel::Window::Hann.coefficients(n);
        let fft = dsp_mel::fft::plan_real_forward::<f64>(n);
        let frames = 1 + samples.len() / hop;
        let mut out = Vec::new();
        for t in 0..frames {
            let mut x: Vec<f64> = (0..n)
                .map(|i| {
                    let k = (t * hop + i) as isize - (n / 2) as isize;
                    let v = usize::try_from(k)
                        .ok()
                        .and_then(|k| samples.get(k))
                        .copied();
                    f64::from(v.unwrap_or(0.0) * window[i])
                })
                .collect();
            let mut spec = fft.make_output_vec();
            fft.process(&mut x, &mut spec).unwrap();
            for band in bank.rows() {
                let p: f64 = spec
                    .iter()
                    .zip(band)
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
        let fast = mel.compute_db(&samples).unwrap();
        let slow = reference_db(22_050, 512, 128, 40, &samples);
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
