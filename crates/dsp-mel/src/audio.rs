//! Mono audio in memory and decoding audio files into it.

use std::path::Path;

use crate::error::{DspError, Result};
use crate::stream::AudioReader;

/// Mono audio: `f32` samples at a known sample rate.
///
/// ```
/// use dsp_mel::Audio;
/// let audio = Audio::new(vec![0.0; 22_050], 22_050)?;
/// assert_eq!(audio.duration_s(), 1.0);
/// # Ok::<(), dsp_mel::DspError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Audio {
    samples: Vec<f32>,
    sample_rate_hz: u32,
}

impl Audio {
    /// Wraps mono samples, checking that there is at least one sample, that every sample is
    /// finite and that the sample rate is positive.
    pub fn new(samples: Vec<f32>, sample_rate_hz: u32) -> Result<Self> {
        if sample_rate_hz == 0 {
            return Err(DspError::InvalidSampleRate(0));
        }
        if samples.is_empty() {
            return Err(DspError::EmptyAudio);
        }
        if let Some(index) = crate::stft::first_non_finite(&samples) {
            return Err(DspError::NonFinite {
                source_name: "<memory>".into(),
                index,
            });
        }
        Ok(Self {
            samples,
            sample_rate_hz,
        })
    }

    /// The samples.
    pub fn samples(&self) -> &[f32] {
        &self.samples
    }

    /// Takes the samples out.
    pub fn into_samples(self) -> Vec<f32> {
        self.samples
    }

    /// Sample rate in Hz.
    pub fn sample_rate_hz(&self) -> u32 {
        self.sample_rate_hz
    }

    /// Duration in seconds.
    pub fn duration_s(&self) -> f64 {
        self.samples.len() as f64 / f64::from(self.sample_rate_hz)
    }

    /// Largest absolute sample value (0 for silence).
    pub fn peak(&self) -> f32 {
        self.samples.iter().fold(0.0f32, |m, s| m.max(s.abs()))
    }
}

/// The rate audio is analysed at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AnalysisRate {
    /// Resample to this rate (the default is [`DEFAULT_ANALYSIS_RATE_HZ`]).
    Hz(u32),
    /// Keep the file's own rate.
    #[default]
    Native,
}

/// The analysis rate the product uses by default (librosa's default too).
pub const DEFAULT_ANALYSIS_RATE_HZ: u32 = 22_050;

/// Decodes an audio file (WAV, FLAC, MP3, OGG/Vorbis; any rate and channel count) and mixes it
/// down to mono `f32` at the file's own sample rate.
///
/// A file cut short (truncated) gives the samples that could be decoded; a file with no
/// decodable sample is an error.
///
/// ```no_run
/// let audio = dsp_mel::load_audio("violin.flac")?;
/// println!("{} s at {} Hz", audio.duration_s(), audio.sample_rate_hz());
/// # Ok::<(), dsp_mel::DspError>(())
/// ```
pub fn load_audio(path: impl AsRef<Path>) -> Result<Audio> {
    read_to_end(AudioReader::open(path)?)
}

/// [`load_audio`] for a file held in memory (see [`AudioReader::from_bytes`]: `label` names
/// it in errors, `extension` helps the format probe).
pub fn load_audio_bytes(bytes: Vec<u8>, label: &Path, extension: Option<&str>) -> Result<Audio> {
    read_to_end(AudioReader::from_bytes(bytes, label, extension)?)
}

/// Every sample `reader` has left, mono.
fn read_to_end(mut reader: AudioReader) -> Result<Audio> {
    let mut samples = Vec::with_capacity(
        reader
            .total_samples_hint()
            .map_or(0, |n| usize::try_from(n).unwrap_or(0).min(1 << 28)),
    );
    while reader.read_mono(1 << 20, &mut samples)? > 0 {}
    Ok(Audio {
        samples,
        sample_rate_hz: reader.sample_rate_hz(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn new_rejects_bad_audio() {
        assert!(matches!(
            Audio::new(vec![], 8000),
            Err(DspError::EmptyAudio)
        ));
        assert!(matches!(
            Audio::new(vec![0.0, f32::NAN], 8000),
            Err(DspError::NonFinite { index: 1, .. })
        ));
        assert!(matches!(
            Audio::new(vec![0.0], 0),
            Err(DspError::InvalidSampleRate(0))
        ));
    }

    /// A 16-bit mono WAV of a 440 Hz sine, 0.5 s at 8 kHz, as bytes.
    fn wav_bytes() -> Vec<u8> {
        let spec = hound::WavSpec {
            channels: 1,
            sample_rate: 8000,
            bits_per_sample: 16,
            sample_format: hound::SampleFormat::Int,
        };
        let mut cursor = std::io::Cursor::new(Vec::new());
        let mut w = hound::WavWriter::new(&mut cursor, spec).unwrap();
        for i in 0..4000 {
            let v = (std::f64::consts::TAU * 440.0 * f64::from(i) / 8000.0).sin() * 10_000.0;
            w.write_sample(v as i16).unwrap();
        }
        w.finalize().unwrap();
        cursor.into_inner()
    }

    #[test]
    fn bytes_decode_as_the_same_file_does() {
        let bytes = wav_bytes();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("tone.wav");
        std::fs::write(&path, &bytes).unwrap();
        let from_file = load_audio(&path).unwrap();
        let from_bytes = load_audio_bytes(bytes.clone(), Path::new("tone"), Some("wav")).unwrap();
        assert_eq!(from_bytes, from_file);
        // No hint: the probe finds the format itself.
        assert_eq!(
            load_audio_bytes(bytes.clone(), Path::new("tone"), None).unwrap(),
            from_file
        );
        // Cut short: what could be decoded, as for a truncated file.
        let cut =
            load_audio_bytes(bytes[..bytes.len() / 2].to_vec(), Path::new("cut"), None).unwrap();
        assert!(cut.samples().len() < 4000 && !cut.samples().is_empty());
        // Not audio, or nothing at all: errors naming the label.
        let e =
            load_audio_bytes(b"not audio at all".to_vec(), Path::new("zone 3"), None).unwrap_err();
        assert!(e.to_string().contains("zone 3"), "{e}");
        assert!(matches!(
            load_audio_bytes(Vec::new(), Path::new("zone 4"), None),
            Err(DspError::EmptyFile { .. })
        ));
    }
}
