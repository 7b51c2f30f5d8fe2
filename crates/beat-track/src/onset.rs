//! Onset strength as `librosa.onset.onset_strength`: mel power → dB → first difference
//! over `lag` frames, half-wave rectified, aggregated over bands, shifted for centred frames.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{first_non_finite, BeatError, Result};
use crate::spectrum::LogMel;

/// How the per-band rectified differences are combined into one value per frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Aggregate {
    /// Mean over bands (`onset_strength`'s default).
    #[default]
    Mean,
    /// Median over bands (what `librosa.beat.beat_track` uses).
    Median,
}

/// Parameters of [`OnsetStrength`]; the defaults are librosa's (22 050 Hz, n_fft 2048,
/// hop 512, 128 Slaney mel bands up to Nyquist, `power_to_db(ref=1, top_db=80)`, lag 1,
/// max_size 1, centred).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OnsetConfig {
    /// Sample rate of the audio in Hz.
    pub sample_rate_hz: u32,
    /// FFT length in samples.
    pub n_fft: usize,
    /// Hop in samples.
    pub hop_length: usize,
    /// Mel bands.
    pub n_mels: usize,
    /// Frames between the compared spectra.
    pub lag: usize,
    /// Size (bands, odd) of the maximum filter over the reference spectrum; 1 = none.
    pub max_size: usize,
    /// Also compute the median over bands ([`OnsetEnvelope::median`] is empty otherwise).
    pub with_median: bool,
}

impl Default for OnsetConfig {
    fn default() -> Self {
        Self {
            sample_rate_hz: dsp_mel::DEFAULT_ANALYSIS_RATE_HZ,
            n_fft: 2048,
            hop_length: 512,
            n_mels: 128,
            lag: 1,
            max_size: 1,
            with_median: false,
        }
    }
}

/// Onset strength curves, one value per STFT frame (`frame t` at `t · hop_s`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OnsetEnvelope {
    /// Seconds between values.
    pub hop_s: f64,
    /// Mean over bands.
    pub mean: Vec<f32>,
    /// Median over bands (empty unless [`OnsetConfig::with_median`]).
    pub median: Vec<f32>,
    /// Loudness of each frame: the mean over bands of the mel spectrum in dB (not shifted:
    /// value `t` describes the frame centred at `t · hop_s`).
    pub loudness_db: Vec<f32>,
}

impl OnsetEnvelope {
    /// The curve of one aggregation.
    pub fn get(&self, aggregate: Aggregate) -> &[f32] {
        match aggregate {
            Aggregate::Mean => &self.mean,
            Aggregate::Median => &self.median,
        }
    }
}

/// A planned onset-strength computation (mel filterbank and FFT built once).
///
/// ```
/// use beat_track::{OnsetConfig, OnsetStrength};
/// let mut x = vec![0.0f32; 22_050];
/// for (i, s) in x.iter_mut().enumerate().skip(11_025) { *s = (i as f32 * 0.3).sin(); }
/// let env = OnsetStrength::new(OnsetConfig::default())?.compute(&x)?;
/// let peak = (0..env.mean.len()).max_by(|&a, &b| env.mean[a].total_cmp(&env.mean[b])).unwrap();
/// assert!((peak as i64 - 22).abs() <= 2); // 0.5 s / 512 samples ≈ frame 21.5
/// # Ok::<(), beat_track::BeatError>(())
/// ```
#[derive(Debug)]
pub struct OnsetStrength {
    cfg: OnsetConfig,
    mel: LogMel,
}

impl OnsetStrength {
    /// Validates `cfg` and plans the spectrogram.
    pub fn new(cfg: OnsetConfig) -> Result<Self> {
        if cfg.lag == 0 || cfg.max_size == 0 || cfg.max_size.is_multiple_of(2) {
            return Err(BeatError::InvalidConfig(format!(
                "lag ({}) must be ≥ 1 and max_size ({}) odd and ≥ 1",
                cfg.lag, cfg.max_size
            )));
        }
        let mel = LogMel::new(cfg.sample_rate_hz, cfg.n_fft, cfg.hop_length, cfg.n_mels)?;
        Ok(Self { cfg, mel })
    }

    /// The configuration.
    pub fn config(&self) -> &OnsetConfig {
        &self.cfg
    }

    /// Onset strength of `samples` (mono, at the configured rate): `1 + len / hop` values.
    pub fn compute(&self, samples: &[f32]) -> Result<OnsetEnvelope> {
        if samples.is_empty() {
            return Err(BeatError::EmptyAudio);
        }
        if let Some(index) = first_non_finite(samples) {
            return Err(BeatError::NonFinite { index });
        }
        let db = self.mel.compute_db(samples)?;
        let bands = self.mel.n_mels().max(1);
        let frames = db.len() / bands;
        let row = |t: usize| &db[t * bands..(t + 1) * bands];
        let lag = self.cfg.lag;
        let pad = lag + self.cfg.n_fft / (2 * self.cfg.hop_length);
        let loudness_db = db
            .par_chunks(bands)
            .map(|r| lane_sum(r) / bands as f32)
            .collect();
        let half = self.cfg.max_size / 2;
        let with_median = self.cfg.with_median;
        // Frame t + lag against frame t, written at t + pad.
        let flux: Vec<(f32, f32)> = (0..frames.saturating_sub(pad))
            .into_par_iter()
            .map_init(
                || (vec![0.0f32; bands], vec![0.0f32; bands]),
                |(diff, reference), t| {
                    let (now, before) = (row(t + lag), row(t));
                    if half > 0 {
                        max_filter(before, half, reference);
                    }
                    let reference = if half == 0 { before } else { &reference[..] };
                    for ((d, &x), &r) in diff.iter_mut().zip(now).zip(reference) {
                        *d = (x - r).max(0.0);
                    }
                    let mean = lane_sum(diff) / bands as f32;
                    (mean, if with_median { median_of(diff) } else { 0.0 })
                },
            )
            .collect();
        let mut mean = vec![0.0f32; frames];
        let mut median = if with_median {
            vec![0.0f32; frames]
        } else {
            Vec::new()
        };
        for (t, (m, med)) in flux.into_iter().enumerate() {
            mean[t + pad] = m;
            if let Some(v) = median.get_mut(t + pad) {
                *v = med;
            }
        }
        Ok(OnsetEnvelope {
            hop_s: self.cfg.hop_length as f64 / f64::from(self.cfg.sample_rate_hz),
            mean,
            median,
            loudness_db,
        })
    }
}

/// scipy's `maximum_filter1d(x, 2 · half + 1, mode="reflect")` (edge sample repeated).
fn max_filter(x: &[f32], half: usize, out: &mut [f32]) {
    let n = x.len();
    for (b, r) in out.iter_mut().enumerate() {
        *r = (b as isize - half as isize..=(b + half) as isize)
            .map(|k| {
                let k = if k < 0 { -k - 1 } else { k } as usize;
                x[if k >= n { 2 * n - k - 1 } else { k }]
            })
            .fold(f32::NEG_INFINITY, f32::max);
    }
}

/// Sum in eight independent lanes (vectorises without reassociation flags).
fn lane_sum(x: &[f32]) -> f32 {
    let mut acc = [0.0f32; 8];
    let chunks = x.chunks_exact(8);
    let tail: f32 = chunks.remainder().iter().sum();
    for c in chunks {
        for k in 0..8 {
            acc[k] += c[k];
        }
    }
    acc.iter().sum::<f32>() + tail
}

/// Median (the mean of the two middle values for an even count), reordering `x`.
fn median_of(x: &mut [f32]) -> f32 {
    let n = x.len();
    if n == 0 {
        return 0.0;
    }
    let (_, &mut upper, _) = x.select_nth_unstable_by(n / 2, f32::total_cmp);
    if n % 2 == 1 {
        upper
    } else {
        let lower = x[..n / 2].iter().copied().fold(f32::NEG_INFINITY, f32::max);
        0.5 * (lower + upper)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_matches_numpy() {
        assert_eq!(median_of(&mut [3.0, 0.0, 1.0, 2.0]), 1.5);
        assert_eq!(median_of(&mut [3.0, 0.0, 1.0]), 1.0);
    }

    #[test]
    fn bad_input_is_an_error() {
        let o = OnsetStrength::new(OnsetConfig::default()).unwrap();
        assert!(matches!(o.compute(&[]), Err(BeatError::EmptyAudio)));
        assert!(matches!(
            o.compute(&[0.0, f32::NAN]),
            Err(BeatError::NonFinite { index: 1 })
        ));
        assert!(OnsetStrength::new(OnsetConfig {
            max_size: 2,
            ..OnsetConfig::default()
        })
        .is_err());
        let silence = o.compute(&[0.0; 4096]).unwrap();
        assert!(silence.mean.iter().all(|&v| v == 0.0));
    }
}
