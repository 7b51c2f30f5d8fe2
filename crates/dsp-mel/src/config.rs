//! Parameters of the short-time Fourier transform and mel filterbank.

use serde::{Deserialize, Serialize};

use crate::error::{DspError, Result};

/// Frequency-to-mel mapping.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum MelScale {
    /// Slaney's Auditory Toolbox scale: linear below 1 kHz, logarithmic above (librosa's default).
    #[default]
    Slaney,
    /// The HTK formula `m = 2595 · log10(1 + f / 700)`.
    Htk,
}

/// Normalisation of each mel filter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum MelNorm {
    /// Divide each triangle by its bandwidth in Hz ("area normalisation", librosa's default).
    #[default]
    Slaney,
    /// Triangles peak at 1.
    None,
}

/// Analysis window (periodic, as `scipy.signal.get_window(..., fftbins=True)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Window {
    /// Periodic Hann window (librosa's default).
    #[default]
    Hann,
    /// Periodic Hamming window.
    Hamming,
    /// No tapering.
    Rectangular,
}

impl Window {
    /// The window's `n` coefficients.
    pub fn coefficients(self, n: usize) -> Vec<f32> {
        let nf = n as f64;
        (0..n)
            .map(|i| {
                let phase = 2.0 * std::f64::consts::PI * i as f64 / nf;
                (match self {
                    Window::Hann => 0.5 - 0.5 * phase.cos(),
                    Window::Hamming => 0.54 - 0.46 * phase.cos(),
                    Window::Rectangular => 1.0,
                }) as f32
            })
            .collect()
    }
}

/// Distance between analysis frames.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Hop {
    /// A fixed hop in samples.
    Samples(usize),
    /// A frame rate; the hop is `round(sample_rate / fps)` samples.
    FramesPerSecond(f64),
}

/// Everything that defines a mel spectrogram. The defaults match
/// `librosa.feature.melspectrogram` (n_fft 2048, hop 512, 128 bands, Hann, centred with zero
/// padding, power 2, Slaney scale and norm).
///
/// ```
/// use dsp_mel::{MelConfig, MelScale};
/// let cfg = MelConfig { mel_scale: MelScale::Htk, ..MelConfig::bowing() };
/// assert_eq!(cfg.hop_length(), 735); // 22 050 Hz / 30 fps
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MelConfig {
    /// Sample rate of the audio the spectrogram is computed from, in Hz.
    pub sample_rate_hz: u32,
    /// FFT length (and window length) in samples.
    pub n_fft: usize,
    /// Frame spacing.
    pub hop: Hop,
    /// Number of mel bands.
    pub n_mels: usize,
    /// Lowest frequency of the filterbank in Hz.
    pub fmin_hz: f64,
    /// Highest frequency in Hz; `None` means Nyquist.
    pub fmax_hz: Option<f64>,
    /// Analysis window.
    pub window: Window,
    /// Pad `n_fft / 2` zeros on both sides so frame `t` is centred at `t · hop`.
    pub center: bool,
    /// Exponent of the magnitude: 2 = power, 1 = magnitude.
    pub power: f32,
    /// Mel scale.
    pub mel_scale: MelScale,
    /// Filter normalisation.
    pub norm: MelNorm,
    /// Average this many consecutive frames (power domain) into one output frame
    /// (frame-rate conversion; 1 = none). A last, incomplete group is averaged over what it has.
    pub pool_frames: usize,
}

impl Default for MelConfig {
    fn default() -> Self {
        Self {
            sample_rate_hz: crate::DEFAULT_ANALYSIS_RATE_HZ,
            n_fft: 2048,
            hop: Hop::Samples(512),
            n_mels: 128,
            fmin_hz: 0.0,
            fmax_hz: None,
            window: Window::Hann,
            center: true,
            power: 2.0,
            mel_scale: MelScale::Slaney,
            norm: MelNorm::Slaney,
            pool_frames: 1,
        }
    }
}

impl MelConfig {
    /// The bowing network's and GRU baseline's input: 30 frames/s × 128 bands at 22 050 Hz
    /// (n_fft 2048, hop 735).
    pub fn bowing() -> Self {
        Self {
            hop: Hop::FramesPerSecond(30.0),
            ..Self::default()
        }
    }

    /// The emotion network's input: 2 frames/s × 64 bands. Computed as a 30 fps, 64-band
    /// power mel spectrogram averaged over groups of 15 frames, so every sample of the audio
    /// contributes (a single 2048-point frame every 0.5 s would skip most of it).
    pub fn emotion() -> Self {
        Self {
            n_mels: 64,
            hop: Hop::FramesPerSecond(30.0),
            pool_frames: 15,
            ..Self::default()
        }
    }

    /// The same configuration for audio at another sample rate (the hop is re-derived when it
    /// is given as a frame rate).
    pub fn at_sample_rate(mut self, sample_rate_hz: u32) -> Self {
        self.sample_rate_hz = sample_rate_hz;
        self
    }

    /// Hop between STFT frames in samples.
    pub fn hop_length(&self) -> usize {
        match self.hop {
            Hop::Samples(h) => h,
            Hop::FramesPerSecond(fps) => {
                let h = (f64::from(self.sample_rate_hz) / fps).round();
                if h.is_finite() && h >= 1.0 {
                    h as usize
                } else {
                    0
                }
            }
        }
    }

    /// Output frames per second (after pooling).
    pub fn output_fps(&self) -> f64 {
        f64::from(self.sample_rate_hz) / (self.hop_length().max(1) * self.pool_frames.max(1)) as f64
    }

    /// Upper edge of the filterbank in Hz.
    pub fn fmax_or_nyquist(&self) -> f64 {
        self.fmax_hz.unwrap_or(f64::from(self.sample_rate_hz) / 2.0)
    }

    /// Checks every field, with a message naming the bad one.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(DspError::InvalidConfig(m));
        if self.sample_rate_hz == 0 {
            return bad("sample_rate_hz must be > 0".into());
        }
        if self.n_fft < 2 {
            return bad(format!("n_fft must be ≥ 2, got {}", self.n_fft));
        }
        if let Hop::FramesPerSecond(fps) = self.hop {
            if !(fps.is_finite() && fps > 0.0) {
                return bad(format!("frames per second must be > 0, got {fps}"));
            }
        }
        if self.hop_length() == 0 {
            return bad("hop must be ≥ 1 sample".into());
        }
        if self.n_mels == 0 {
            return bad("n_mels must be ≥ 1".into());
        }
        let fmax = self.fmax_or_nyquist();
        if !(self.fmin_hz.is_finite() && self.fmin_hz >= 0.0) {
            return bad(format!("fmin_hz must be ≥ 0, got {}", self.fmin_hz));
        }
        if !(fmax.is_finite() && fmax > self.fmin_hz) {
            return bad(format!(
                "fmax_hz ({fmax}) must be above fmin_hz ({})",
                self.fmin_hz
            ));
        }
        if !(self.power.is_finite() && self.power > 0.0) {
            return bad(format!("power must be > 0, got {}", self.power));
        }
        if self.pool_frames == 0 {
            return bad("pool_frames must be ≥ 1".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_have_the_spec_rates() {
        let b = MelConfig::bowing();
        assert_eq!((b.n_mels, b.hop_length()), (128, 735));
        assert!((b.output_fps() - 30.0).abs() < 1e-9);
        let e = MelConfig::emotion();
        assert_eq!(e.n_mels, 64);
        assert!((e.output_fps() - 2.0).abs() < 1e-9);
        let b44 = MelConfig::bowing().at_sample_rate(44_100);
        assert_eq!(b44.hop_length(), 1470);
    }

    #[test]
    fn validate_names_the_bad_field() {
        let cfg = MelConfig {
            n_mels: 0,
            ..MelConfig::default()
        };
        let msg = cfg.validate().unwrap_err().to_string();
        assert!(msg.contains("n_mels"), "{msg}");
        let cfg = MelConfig {
            fmin_hz: 20_000.0,
            ..MelConfig::default()
        };
        assert!(cfg.validate().is_err());
        let cfg = MelConfig {
            hop: Hop::FramesPerSecond(f64::NAN),
            ..MelConfig::default()
        };
        assert!(cfg.validate().is_err());
    }

    #[test]
    fn hann_is_periodic() {
        let w = Window::Hann.coefficients(4);
        assert_eq!(w, vec![0.0, 0.5, 1.0, 0.5]);
    }
}
