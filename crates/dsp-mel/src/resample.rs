//! Sample-rate conversion with rubato's synchronous FFT resampler.

use audioadapter_buffers::direct::InterleavedSlice;
use rubato::{Fft, FixedSync, Resampler};

use crate::audio::{load_audio, AnalysisRate, Audio};
use crate::error::{DspError, Result};

/// Highest rate we accept, in or out.
const MAX_RATE_HZ: u32 = 768_000;

/// Resamples mono audio to `target_hz` (a copy when the rate already matches).
///
/// Uses rubato's FFT resampler (band-limited, fixed ratio) and trims its delay, so the output
/// is time-aligned with the input and has `ceil(len · target / source)` samples.
///
/// ```
/// let audio = dsp_mel::Audio::new(vec![0.1; 44_100], 44_100)?;
/// let half = dsp_mel::resample(&audio, 22_050)?;
/// assert_eq!(half.samples().len(), 22_050);
/// # Ok::<(), dsp_mel::DspError>(())
/// ```
pub fn resample(audio: &Audio, target_hz: u32) -> Result<Audio> {
    if target_hz == 0 || target_hz > MAX_RATE_HZ {
        return Err(DspError::InvalidSampleRate(target_hz));
    }
    let source_hz = audio.sample_rate_hz();
    if source_hz == target_hz {
        return Ok(audio.clone());
    }
    if source_hz > MAX_RATE_HZ {
        return Err(DspError::InvalidSampleRate(source_hz));
    }
    let input = audio.samples();
    let mut resampler = Fft::<f32>::new(
        source_hz as usize,
        target_hz as usize,
        1024,
        1,
        FixedSync::Input,
    )
    .map_err(|e| DspError::Resample(e.to_string()))?;
    let adapter = InterleavedSlice::new(input, 1, input.len())
        .map_err(|e| DspError::Resample(e.to_string()))?;
    let out = resampler
        .process_all(&adapter, input.len(), None)
        .map_err(|e| DspError::Resample(e.to_string()))?;
    let mut samples = out.take_data();
    if samples.is_empty() {
        samples.push(0.0);
    }
    Audio::new(samples, target_hz)
}

/// Decodes an audio file and resamples it to `rate`.
pub fn load_audio_at(path: impl AsRef<std::path::Path>, rate: AnalysisRate) -> Result<Audio> {
    let audio = load_audio(path)?;
    match rate {
        AnalysisRate::Native => Ok(audio),
        AnalysisRate::Hz(hz) => resample(&audio, hz),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sine(freq: f32, rate: u32, secs: f32) -> Audio {
        let n = (rate as f32 * secs) as usize;
        let samples = (0..n)
            .map(|i| (2.0 * std::f32::consts::PI * freq * i as f32 / rate as f32).sin())
            .collect();
        Audio::new(samples, rate).unwrap()
    }

    #[test]
    fn length_and_alignment_are_kept() {
        let a = sine(440.0, 44_100, 1.0);
        let b = resample(&a, 22_050).unwrap();
        assert_eq!(b.samples().len(), 22_050);
        // Compare against the analytic sine away from the edges: delay must be trimmed.
        let err = b.samples()[2000..20000]
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let t = (i + 2000) as f32 / 22_050.0;
                (s - (2.0 * std::f32::consts::PI * 440.0 * t).sin()).abs()
            })
            .fold(0.0f32, f32::max);
        assert!(err < 1e-3, "max error {err}");
    }

    #[test]
    fn same_rate_is_identity_and_bad_rates_error() {
        let a = sine(440.0, 8000, 0.1);
        assert_eq!(resample(&a, 8000).unwrap(), a);
        assert!(matches!(
            resample(&a, 0),
            Err(DspError::InvalidSampleRate(0))
        ));
    }

    #[test]
    fn one_sample_upsampled_does_not_panic() {
        let a = Audio::new(vec![0.5], 8000).unwrap();
        let b = resample(&a, 44_100).unwrap();
        assert!(!b.samples().is_empty());
    }
}
