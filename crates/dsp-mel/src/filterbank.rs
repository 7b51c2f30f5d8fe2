//! Mel scale conversions and the triangular mel filterbank (as `librosa.filters.mel`).

use ndarray::Array2;

use crate::config::{MelConfig, MelNorm, MelScale};
use crate::error::Result;

const SLANEY_F_SP: f64 = 200.0 / 3.0;
const SLANEY_MIN_LOG_HZ: f64 = 1000.0;
const SLANEY_MIN_LOG_MEL: f64 = SLANEY_MIN_LOG_HZ / SLANEY_F_SP;

fn slaney_logstep() -> f64 {
    6.4f64.ln() / 27.0
}

/// Converts a frequency in Hz to mels.
///
/// ```
/// use dsp_mel::{hz_to_mel, MelScale};
/// assert!((hz_to_mel(1000.0, MelScale::Slaney) - 15.0).abs() < 1e-12);
/// assert!((hz_to_mel(700.0, MelScale::Htk) - 2595.0 * 2f64.log10()).abs() < 1e-9);
/// ```
pub fn hz_to_mel(hz: f64, scale: MelScale) -> f64 {
    match scale {
        MelScale::Htk => 2595.0 * (1.0 + hz / 700.0).log10(),
        MelScale::Slaney => {
            if hz >= SLANEY_MIN_LOG_HZ {
                SLANEY_MIN_LOG_MEL + (hz / SLANEY_MIN_LOG_HZ).ln() / slaney_logstep()
            } else {
                hz / SLANEY_F_SP
            }
        }
    }
}

/// Converts mels to a frequency in Hz (inverse of [`hz_to_mel`]).
pub fn mel_to_hz(mel: f64, scale: MelScale) -> f64 {
    match scale {
        MelScale::Htk => 700.0 * (10f64.powf(mel / 2595.0) - 1.0),
        MelScale::Slaney => {
            if mel >= SLANEY_MIN_LOG_MEL {
                SLANEY_MIN_LOG_HZ * (slaney_logstep() * (mel - SLANEY_MIN_LOG_MEL)).exp()
            } else {
                SLANEY_F_SP * mel
            }
        }
    }
}

/// `n` frequencies evenly spaced on the mel scale from `fmin_hz` to `fmax_hz`.
pub fn mel_frequencies(n: usize, fmin_hz: f64, fmax_hz: f64, scale: MelScale) -> Vec<f64> {
    let lo = hz_to_mel(fmin_hz, scale);
    let hi = hz_to_mel(fmax_hz, scale);
    (0..n)
        .map(|i| {
            let t = if n > 1 {
                i as f64 / (n - 1) as f64
            } else {
                0.0
            };
            mel_to_hz(lo + (hi - lo) * t, scale)
        })
        .collect()
}

/// The dense filterbank, shape `(n_mels, n_fft / 2 + 1)`, equal to
/// `librosa.filters.mel(sr=..., n_fft=..., n_mels=..., fmin=..., fmax=..., htk=..., norm=...)`.
pub fn mel_filterbank(cfg: &MelConfig) -> Result<Array2<f32>> {
    cfg.validate()?;
    let n_bins = cfg.n_fft / 2 + 1;
    let sr = f64::from(cfg.sample_rate_hz);
    let fft_freqs: Vec<f64> = (0..n_bins)
        .map(|k| k as f64 * sr / cfg.n_fft as f64)
        .collect();
    let mel_f = mel_frequencies(
        cfg.n_mels + 2,
        cfg.fmin_hz,
        cfg.fmax_or_nyquist(),
        cfg.mel_scale,
    );
    let mut weights = Array2::<f32>::zeros((cfg.n_mels, n_bins));
    for m in 0..cfg.n_mels {
        let (f0, f1, f2) = (mel_f[m], mel_f[m + 1], mel_f[m + 2]);
        let (d0, d1) = (f1 - f0, f2 - f1);
        let enorm = match cfg.norm {
            MelNorm::Slaney => 2.0 / (f2 - f0),
            MelNorm::None => 1.0,
        };
        for (k, &f) in fft_freqs.iter().enumerate() {
            let lower = (f - f0) / d0;
            let upper = (f2 - f) / d1;
            let w = lower.min(upper).max(0.0);
            // librosa stores the triangle as float32, then scales it in float32.
            weights[[m, k]] = (w as f32) * (enorm as f32);
        }
    }
    Ok(weights)
}

/// One mel band stored sparsely: the weights of the FFT bins `start..start + weights.len()`.
#[derive(Debug, Clone)]
pub(crate) struct SparseBand {
    pub start: usize,
    pub weights: Vec<f32>,
}

/// Keeps only the non-zero run of each band (triangles are contiguous), so applying the
/// filterbank costs about two multiply-adds per FFT bin instead of `n_mels`.
pub(crate) fn sparse_bands(dense: &Array2<f32>) -> Vec<SparseBand> {
    dense
        .rows()
        .into_iter()
        .map(|row| {
            let first = row.iter().position(|&w| w != 0.0);
            let last = row.iter().rposition(|&w| w != 0.0);
            match (first, last) {
                (Some(a), Some(b)) => SparseBand {
                    start: a,
                    weights: row.iter().skip(a).take(b - a + 1).copied().collect(),
                },
                _ => SparseBand {
                    start: 0,
                    weights: Vec::new(),
                },
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scales_round_trip() {
        for scale in [MelScale::Slaney, MelScale::Htk] {
            for hz in [0.0, 100.0, 999.0, 1000.0, 4000.0, 11_025.0] {
                let back = mel_to_hz(hz_to_mel(hz, scale), scale);
                assert!(
                    (back - hz).abs() < 1e-6 * hz.max(1.0),
                    "{scale:?} {hz} {back}"
                );
            }
        }
    }

    #[test]
    fn sparse_equals_dense() {
        let cfg = MelConfig::default();
        let dense = mel_filterbank(&cfg).unwrap();
        let bands = sparse_bands(&dense);
        for (m, band) in bands.iter().enumerate() {
            let total: f32 = dense.row(m).sum();
            let sparse: f32 = band.weights.iter().sum();
            assert!((total - sparse).abs() <= 1e-6 * total.abs().max(1e-12));
        }
    }
}
