//! Checks and windowing of a `(frames, bands)` spectrogram as the networks take it: the input
//! checks every network runs before inference, and the copy of a run of frames (padded with
//! silence outside the recording) into a window buffer.

use ndarray::ArrayView2;

/// An input spectrogram the networks cannot use (empty, wrong width, non-finite values); the
/// message says what is wrong and what to do.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

/// Checks a `(frames, bands)` input: at least one frame, `bands` wide, every value finite.
///
/// ```
/// let mel = ndarray::Array2::<f32>::zeros((3, 4));
/// assert!(net_core::frames::check_mel(mel.view(), 4).is_ok());
/// assert!(net_core::frames::check_mel(mel.view(), 5).is_err());
/// ```
pub fn check_mel(mel: ArrayView2<f32>, bands: usize) -> Result<(), InputError> {
    let (frames, width) = mel.dim();
    if frames == 0 {
        return Err(InputError(
            "the spectrogram has no frames (empty or too short audio)".into(),
        ));
    }
    if width != bands {
        return Err(InputError(format!(
            "the spectrogram has {width} bands, the network takes {bands}: use the matching mel configuration"
        )));
    }
    if let Some(pos) = mel.iter().position(|v| !v.is_finite()) {
        return Err(InputError(format!(
            "the spectrogram holds a non-finite value at frame {}",
            pos / width.max(1)
        )));
    }
    Ok(())
}

/// The value used for frames before the start and after the end of a recording: its
/// quietest value (silence).
pub fn pad_value(mel: ArrayView2<f32>) -> f32 {
    mel.iter().copied().fold(f32::INFINITY, f32::min)
}

/// Copies `len` frames of `mel` starting at frame `first` (may be negative or run past the
/// end: those frames are `pad`) into `dst` (`len × bands`).
///
/// ```
/// let mel = ndarray::array![[1.0f32, 2.0], [3.0, 4.0]];
/// let mut dst = [0.0f32; 6];
/// net_core::frames::copy_frames(mel.view(), -1, 3, -9.0, &mut dst);
/// assert_eq!(dst, [-9.0, -9.0, 1.0, 2.0, 3.0, 4.0]);
/// ```
pub fn copy_frames(mel: ArrayView2<f32>, first: isize, len: usize, pad: f32, dst: &mut [f32]) {
    let bands = mel.ncols();
    for (k, row) in dst.chunks_exact_mut(bands).take(len).enumerate() {
        let f = first + k as isize;
        if f >= 0 && (f as usize) < mel.nrows() {
            for (d, s) in row.iter_mut().zip(mel.row(f as usize)) {
                *d = *s;
            }
        } else {
            row.fill(pad);
        }
    }
}
