//! The network input: 30 fps × 128-band mel spectrogram in dB at 22 050 Hz.

use std::path::Path;

use dsp_mel::{resample, Audio, DbConfig, MelConfig, MelSpectrogram, DEFAULT_ANALYSIS_RATE_HZ};
use ndarray::{Array2, ArrayView2};

use crate::error::{NetError, Result};

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

/// Checks a `(frames, bands)` input: at least one frame, `bands` wide, every value finite.
pub fn check_mel(mel: ArrayView2<f32>, bands: usize) -> Result<()> {
    let (frames, width) = mel.dim();
    if frames == 0 {
        return Err(NetError::Input(
            "the spectrogram has no frames (empty or too short audio)".into(),
        ));
    }
    if width != bands {
        return Err(NetError::Input(format!(
            "the spectrogram has {width} bands, the network takes {bands}: use the matching mel configuration"
        )));
    }
    if let Some(pos) = mel.iter().position(|v| !v.is_finite()) {
        return Err(NetError::Input(format!(
            "the spectrogram holds a non-finite value at frame {}",
            pos / width.max(1)
        )));
    }
    Ok(())
}

/// Frame index (rounded) of a time in seconds at [`FPS`].
pub fn frame_of(time_s: f64) -> usize {
    (time_s * FPS).round().max(0.0) as usize
}
