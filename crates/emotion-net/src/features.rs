//! The network input: 2 fps × 64-band mel spectrogram in dB at 22 050 Hz.

use std::path::Path;

use dsp_mel::{resample, Audio, DbConfig, MelConfig, MelSpectrogram, DEFAULT_ANALYSIS_RATE_HZ};
use ndarray::Array2;

use crate::error::Result;

/// Arousal values (and input frames) per second.
pub const RATE_HZ: f64 = 2.0;

/// The 2 fps × 64 mel dB spectrogram (`MelConfig::emotion()`, `DbConfig::default()`) of
/// `audio`, resampled to 22 050 Hz first when needed.
pub fn emotion_mel(audio: &Audio) -> Result<Array2<f32>> {
    let audio = if audio.sample_rate_hz() == DEFAULT_ANALYSIS_RATE_HZ {
        audio.clone()
    } else {
        resample(audio, DEFAULT_ANALYSIS_RATE_HZ)?
    };
    let mel = MelSpectrogram::new(MelConfig::emotion())?;
    Ok(mel.compute_db(audio.samples(), &DbConfig::default())?)
}

/// [`emotion_mel`] of an audio file.
pub fn emotion_mel_of_file(path: &Path) -> Result<Array2<f32>> {
    emotion_mel(&dsp_mel::load_audio(path)?)
}
