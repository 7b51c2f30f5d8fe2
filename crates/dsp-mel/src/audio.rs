//! Mono audio in memory and decoding audio files into it.

use std::fs::File;
use std::path::Path;

use symphonia::core::codecs::audio::AudioDecoderOptions;
use symphonia::core::errors::Error as SymError;
use symphonia::core::formats::probe::Hint;
use symphonia::core::formats::{FormatOptions, TrackType};
use symphonia::core::io::MediaSourceStream;
use symphonia::core::meta::MetadataOptions;

use crate::error::{DspError, Result};

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
        if let Some(index) = crate::mel::first_non_finite(&samples) {
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
    let path = path.as_ref();
    let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => DspError::NotFound { path: path.into() },
        _ => DspError::Io {
            path: path.into(),
            source: e,
        },
    })?;
    if meta.is_dir() {
        return Err(DspError::IsDirectory { path: path.into() });
    }
    if meta.len() == 0 {
        return Err(DspError::EmptyFile { path: path.into() });
    }
    let file = File::open(path).map_err(|e| DspError::Io {
        path: path.into(),
        source: e,
    })?;
    let (samples, rate) = decode(file, path)?;
    if samples.is_empty() {
        return Err(DspError::NoSamples { path: path.into() });
    }
    if let Some(index) = crate::mel::first_non_finite(&samples) {
        return Err(DspError::NonFinite {
            source_name: path.display().to_string(),
            index,
        });
    }
    if rate == 0 {
        return Err(DspError::Corrupt {
            path: path.into(),
            reason: "sample rate is 0".into(),
        });
    }
    Ok(Audio {
        samples,
        sample_rate_hz: rate,
    })
}

/// Decodes an audio file and resamples it to `rate`.
pub fn load_audio_at(path: impl AsRef<Path>, rate: AnalysisRate) -> Result<Audio> {
    let audio = load_audio(path)?;
    match rate {
        AnalysisRate::Native => Ok(audio),
        AnalysisRate::Hz(hz) => crate::resample::resample(&audio, hz),
    }
}

/// How many undecodable packets in a row we skip before calling the file corrupt.
const MAX_CONSECUTIVE_BAD_PACKETS: usize = 16;

fn decode(file: File, path: &Path) -> Result<(Vec<f32>, u32)> {
    let unsupported = |reason: String| DspError::Unsupported {
        path: path.into(),
        reason,
    };
    let corrupt = |reason: String| DspError::Corrupt {
        path: path.into(),
        reason,
    };
    let mss = MediaSourceStream::new(Box::new(file), Default::default());
    let mut hint = Hint::new();
    if let Some(ext) = path.extension().and_then(|e| e.to_str()) {
        hint.with_extension(ext);
    }
    let mut format = symphonia::default::get_probe()
        .probe(
            &hint,
            mss,
            FormatOptions::default(),
            MetadataOptions::default(),
        )
        .map_err(|e| unsupported(e.to_string()))?;
    let track = format
        .default_track(TrackType::Audio)
        .ok_or_else(|| unsupported("no audio track".into()))?;
    let track_id = track.id;
    let params = track
        .codec_params
        .as_ref()
        .and_then(|p| p.audio())
        .ok_or_else(|| unsupported("no audio codec parameters".into()))?;
    let mut rate = params.sample_rate.unwrap_or(0);
    let mut decoder = symphonia::default::get_codecs()
        .make_audio_decoder(params, &AudioDecoderOptions::default())
        .map_err(|e| unsupported(e.to_string()))?;

    let mut mono: Vec<f32> = Vec::new();
    let mut interleaved: Vec<f32> = Vec::new();
    let mut bad_in_a_row = 0usize;
    let mut last_decode_error = String::new();
    loop {
        let packet = match format.next_packet() {
            Ok(Some(p)) => p,
            Ok(None) => break,
            // A file cut short ends the stream: keep what was decoded.
            Err(SymError::IoError(_)) => break,
            Err(SymError::ResetRequired) => break,
            Err(e) => {
                if mono.is_empty() {
                    return Err(corrupt(e.to_string()));
                }
                break;
            }
        };
        if packet.track_id != track_id {
            continue;
        }
        match decoder.decode(&packet) {
            Ok(buf) => {
                bad_in_a_row = 0;
                let channels = buf.spec().channels().count().max(1);
                if rate == 0 {
                    rate = buf.spec().rate();
                }
                buf.copy_to_vec_interleaved(&mut interleaved);
                mix_down_into(&interleaved, channels, &mut mono);
            }
            Err(SymError::DecodeError(e)) => {
                last_decode_error = e.to_string();
                bad_in_a_row += 1;
            }
            Err(SymError::IoError(e)) => {
                last_decode_error = e.to_string();
                bad_in_a_row += 1;
            }
            Err(e) => return Err(corrupt(e.to_string())),
        }
        if bad_in_a_row > MAX_CONSECUTIVE_BAD_PACKETS {
            return Err(corrupt(last_decode_error));
        }
    }
    if mono.is_empty() && !last_decode_error.is_empty() {
        return Err(corrupt(last_decode_error));
    }
    Ok((mono, rate))
}

/// Averages interleaved channels into `out` (appending).
fn mix_down_into(interleaved: &[f32], channels: usize, out: &mut Vec<f32>) {
    if channels == 1 {
        out.extend_from_slice(interleaved);
        return;
    }
    let scale = 1.0 / channels as f32;
    out.extend(
        interleaved
            .chunks_exact(channels)
            .map(|frame| frame.iter().sum::<f32>() * scale),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mixdown_averages_channels() {
        let mut out = Vec::new();
        mix_down_into(&[1.0, 3.0, -1.0, 1.0], 2, &mut out);
        assert_eq!(out, vec![2.0, 0.0]);
    }

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
}
