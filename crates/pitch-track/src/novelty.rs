//! Onset novelty for note segmentation: SuperFlux-style spectral flux (Böck & Widmer 2013)
//! on a log-mel spectrogram, on the pitch track's frame grid.
//!
//! `novelty[t] = mean_b max(0, S[t, b] − max(S[t − lag, b − 1 ..= b + 1]))` with `S` in dB.
//! The maximum over neighbouring bands of the earlier frame keeps vibrato (harmonics moving
//! between bands) from looking like onsets, while a re-attack (energy rising in every band,
//! bow noise) still does.

use dsp_mel::{DbConfig, DbRef, Hop, MelConfig, MelSpectrogram};
use serde::{Deserialize, Serialize};

use crate::error::{first_non_finite, PitchError, Result};

/// Parameters of [`onset_novelty`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NoveltyConfig {
    /// FFT length in samples.
    pub n_fft: usize,
    /// Mel bands.
    pub n_mels: usize,
    /// Lowest band edge in Hz.
    pub fmin_hz: f64,
    /// Frames between the compared spectra.
    pub lag: usize,
    /// Width (bands) of the maximum filter over the earlier frame.
    pub max_size: usize,
}

impl Default for NoveltyConfig {
    fn default() -> Self {
        Self {
            n_fft: 1024,
            n_mels: 64,
            fmin_hz: 150.0,
            lag: 2,
            max_size: 3,
        }
    }
}

/// Onset novelty of `samples` with one value per hop (`1 + len / hop_length` values, frame
/// `t` centred at `t · hop_length` samples, as the pitch track's frames).
///
/// ```
/// let sr = 22_050;
/// let mut x = vec![0.0f32; sr];
/// for (i, s) in x.iter_mut().enumerate().skip(sr / 2) { *s = (i as f32 * 0.2).sin(); }
/// let nov = pitch_track::onset_novelty(&x, sr as u32, 256, &Default::default())?;
/// let peak = (0..nov.len()).max_by(|&a, &b| nov[a].total_cmp(&nov[b])).unwrap();
/// assert!((peak as i64 - 43).abs() <= 3); // 0.5 s / 256 samples
/// # Ok::<(), pitch_track::PitchError>(())
/// ```
pub fn onset_novelty(
    samples: &[f32],
    sample_rate_hz: u32,
    hop_length: usize,
    cfg: &NoveltyConfig,
) -> Result<Vec<f32>> {
    if samples.is_empty() {
        return Err(PitchError::EmptyAudio);
    }
    if let Some(index) = first_non_finite(samples) {
        return Err(PitchError::NonFinite { index });
    }
    if cfg.lag == 0 || cfg.max_size == 0 {
        return Err(PitchError::InvalidConfig(
            "novelty lag and max_size must be ≥ 1".into(),
        ));
    }
    let mel = MelSpectrogram::new(MelConfig {
        sample_rate_hz,
        n_fft: cfg.n_fft,
        hop: Hop::Samples(hop_length),
        n_mels: cfg.n_mels,
        fmin_hz: cfg.fmin_hz,
        ..MelConfig::default()
    })?;
    let db = mel.compute_db(
        samples,
        &DbConfig {
            reference: DbRef::Max,
            amin: 1e-10,
            top_db: Some(80.0),
        },
    )?;
    let (frames, bands) = db.dim();
    let half = cfg.max_size / 2;
    let mut out = vec![0.0f32; frames];
    for t in cfg.lag..frames {
        let now = db.row(t);
        let before = db.row(t - cfg.lag);
        let mut acc = 0.0f32;
        for b in 0..bands {
            let lo = b.saturating_sub(half);
            let hi = (b + half + 1).min(bands);
            let reference = (lo..hi)
                .map(|k| before[k])
                .fold(f32::NEG_INFINITY, f32::max);
            acc += (now[b] - reference).max(0.0);
        }
        // Attribute the rise to the middle of the compared frames.
        out[t - cfg.lag / 2] = acc / bands as f32;
    }
    Ok(out)
}
