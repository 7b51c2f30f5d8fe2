//! The network's input: a 30 fps × 128-band mel spectrogram in dB, and checks on it.

use dsp_mel::{Audio, DbConfig, MelConfig, MelSpectrogram};
use ndarray::{Array2, ArrayView2};

use crate::error::{GruError, Result};

/// Audio is resampled to this rate before the mel spectrogram (the product's analysis rate).
pub const MEL_SAMPLE_RATE_HZ: u32 = dsp_mel::DEFAULT_ANALYSIS_RATE_HZ;

/// Frames per second of the mel input and of the skeleton.
pub const FPS: f64 = 30.0;

/// `dsp_mel::MelConfig::bowing()` (30 fps × 128 bands, Slaney) at 22 050 Hz, then
/// `power_to_db` with librosa's defaults: `(frames, 128)`. Mel frame `t` is centred at
/// `t / 30` s, like skeleton frame `t`.
///
/// ```
/// let tone: Vec<f32> = (0..22_050).map(|i| (i as f32 * 0.05).sin()).collect();
/// let mel = gru_baseline::features::mel_frames(&dsp_mel::Audio::new(tone, 22_050)?)?;
/// assert_eq!(mel.dim(), (31, 128));
/// # Ok::<(), gru_baseline::GruError>(())
/// ```
pub fn mel_frames(audio: &Audio) -> Result<Array2<f32>> {
    let audio = dsp_mel::resample(audio, MEL_SAMPLE_RATE_HZ)?;
    let mel = MelSpectrogram::new(MelConfig::bowing().at_sample_rate(MEL_SAMPLE_RATE_HZ))?;
    Ok(mel.compute_db(audio.samples(), &DbConfig::default())?)
}

/// Checks a mel input: `(frames ≥ 1, bands)` and every value finite.
pub fn check_mel(mel: ArrayView2<f32>, bands: usize, what: &str) -> Result<()> {
    if mel.ncols() != bands {
        return Err(GruError::Shape {
            what: what.into(),
            expected: format!("(frames, {bands})"),
            got: format!("{:?}", mel.dim()),
        });
    }
    if mel.nrows() == 0 {
        return Err(GruError::Empty(what.into()));
    }
    if let Some(index) = mel.iter().position(|v| !v.is_finite()) {
        return Err(GruError::NonFinite {
            what: what.into(),
            index,
        });
    }
    Ok(())
}

/// Truncates mel frames and joint frames to the shorter of the two (both 30 fps, frame `t`
/// at `t / 30` s).
pub fn align(mel: Array2<f32>, joints: Array2<f32>) -> (Array2<f32>, Array2<f32>) {
    let n = mel.nrows().min(joints.nrows());
    let cut = |a: Array2<f32>| -> Array2<f32> {
        if a.nrows() == n {
            a
        } else {
            a.slice(ndarray::s![..n, ..]).to_owned()
        }
    };
    (cut(mel), cut(joints))
}
