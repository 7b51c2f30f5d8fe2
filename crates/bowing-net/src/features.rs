//! The network input: 30 fps × 128-band mel spectrogram in dB at 22 050 Hz.

use std::path::Path;

use dsp_mel::{resample, Audio, DbConfig, MelConfig, MelSpectrogram, DEFAULT_ANALYSIS_RATE_HZ};
use ndarray::Array2;

use crate::error::Result;

/// Frames per second of the bowing network's input and output.
pub const FPS: f64 = 30.0;

/// The 30 fps × 128 mel dB spectrogram (`MelConfig::bowing()`, `DbConfig::default()`) of
/// `audio`, resampled to 22 050 Hz first when needed.
pub fn bowing_mel(audio: &Audio) -> Result<Array2<f32>> {
    let audio = if audio.sample_rate_hz() == DEFAULT_ANALYSIS_RATE_HZ {
        audio.clone()
    } else {
        resample(audio, DEFAULT_ANALYSIS_RATE_HZ)?
    };
    let mel = MelSpectrogram::new(MelConfig::bowing())?;
    Ok(mel.compute_db(audio.samples(), &DbConfig::default())?)
}

/// [`bowing_mel`] of an audio file.
pub fn bowing_mel_of_file(path: &Path) -> Result<Array2<f32>> {
    bowing_mel(&dsp_mel::load_audio(path)?)
}

/// Frame index (rounded) of a time in seconds at [`FPS`].
pub fn frame_of(time_s: f64) -> usize {
    (time_s * FPS).round().max(0.0) as usize
}
