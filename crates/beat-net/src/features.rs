//! The network's input frames: the 30 fps × 128 mel dB spectrogram (the same one the bowing
//! network reads), made independent of the recording's level, plus two per-frame features.
//!
//! * **Gain**: every value is taken relative to the recording's reference level, the
//!   [`REFERENCE_PERCENTILE`]th percentile of the frames' loudest band, floored at
//!   [`REFERENCE_FLOOR_DB`] (so a recording at −20 dBFS looks like the same one at −1 dBFS,
//!   while silence or faint noise is not blown up to full level). Values are then clipped to
//!   [`RANGE_DB`] below the reference.
//! * **Extra features** ([`EXTRA_FEATURES`]): the positive spectral flux (mean over bands of
//!   the rise from the previous frame, dB/10) and the frame's loudest band (dB/10).
//!
//! The per-band standardisation that follows is part of the model (its weights file).

use ndarray::{Array2, ArrayView2};

use crate::error::Result;

/// Frames per second of the input and the activations.
pub const FPS: f64 = 30.0;
/// Mel bands of the input spectrogram.
pub const N_MELS: usize = 128;
/// Features appended to the mel bands of every frame.
pub const EXTRA_FEATURES: usize = 2;
/// Percentile of the frames' loudest band used as the recording's reference level.
pub const REFERENCE_PERCENTILE: f64 = 95.0;
/// The lowest reference level (dB, as `DbConfig::default()` measures): quieter recordings
/// are not raised further.
pub const REFERENCE_FLOOR_DB: f32 = -70.0;
/// Values more than this far below the reference are clipped.
pub const RANGE_DB: f32 = 80.0;

/// Features per input frame (mel bands plus [`EXTRA_FEATURES`]).
pub const fn input_features(n_mels: usize) -> usize {
    n_mels + EXTRA_FEATURES
}

/// The recording's reference level (see the module docs) of a `(frames, bands)` dB array.
///
/// ```
/// let mel = ndarray::Array2::from_shape_fn((100, 4), |(t, b)| -30.0 - b as f32 + (t % 2) as f32);
/// assert_eq!(beat_net::features::reference_level(mel.view()), -29.0);
/// let silence = ndarray::Array2::from_elem((10, 4), -100.0f32);
/// assert_eq!(beat_net::features::reference_level(silence.view()), -70.0);
/// ```
pub fn reference_level(mel_db: ArrayView2<f32>) -> f32 {
    let mut loudest: Vec<f32> = mel_db
        .rows()
        .into_iter()
        .map(|r| r.iter().copied().fold(f32::NEG_INFINITY, f32::max))
        .filter(|v| v.is_finite())
        .collect();
    if loudest.is_empty() {
        return REFERENCE_FLOOR_DB;
    }
    loudest.sort_by(f32::total_cmp);
    let k = ((REFERENCE_PERCENTILE / 100.0) * (loudest.len() - 1) as f64).round() as usize;
    loudest[k.min(loudest.len() - 1)].max(REFERENCE_FLOOR_DB)
}

/// The input frames `(frames, n_mels + EXTRA_FEATURES)` of a mel dB spectrogram
/// `(frames, n_mels)` (module docs). Fails on an empty or non-finite spectrogram.
pub fn frame_features(mel_db: ArrayView2<f32>) -> Result<Array2<f32>> {
    net_core::frames::check_mel(mel_db, mel_db.ncols().max(1))?;
    let (frames, bands) = mel_db.dim();
    let reference = reference_level(mel_db);
    let mut out = Array2::<f32>::zeros((frames, input_features(bands)));
    let mut previous: Option<Vec<f32>> = None;
    for (t, row) in mel_db.rows().into_iter().enumerate() {
        let rel: Vec<f32> = row
            .iter()
            .map(|v| (v - reference).clamp(-RANGE_DB, RANGE_DB))
            .collect();
        let flux = previous.as_ref().map_or(0.0, |p| {
            rel.iter()
                .zip(p)
                .map(|(a, b)| (a - b).max(0.0))
                .sum::<f32>()
                / bands as f32
        });
        let loudest = rel.iter().copied().fold(-RANGE_DB, f32::max);
        let mut dst = out.row_mut(t);
        for (d, v) in dst.iter_mut().zip(&rel) {
            *d = *v;
        }
        dst[bands] = flux / 10.0;
        dst[bands + 1] = loudest / 10.0;
        previous = Some(rel);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_changes_do_not_change_the_features() {
        let mel = Array2::from_shape_fn((300, 8), |(t, b)| {
            -40.0 + 10.0 * ((t as f32 * 0.3 + b as f32).sin()) - if t % 15 == 0 { 0.0 } else { 6.0 }
        });
        let quiet = mel.mapv(|v| v - 19.0);
        let a = frame_features(mel.view()).unwrap();
        let b = frame_features(quiet.view()).unwrap();
        assert_eq!(a.dim(), (300, 10));
        let diff = (&a - &b).mapv(f32::abs).fold(0.0f32, |m, v| m.max(*v));
        assert!(diff < 1e-3, "{diff}");
        // Onsets every 15 frames give flux there.
        assert!(a[[15, 8]] > a[[16, 8]]);
    }

    #[test]
    fn silence_stays_quiet_and_bad_input_is_refused() {
        let silence = Array2::from_elem((50, 8), -100.0f32);
        let f = frame_features(silence.view()).unwrap();
        assert!(f.iter().all(|v| v.is_finite()));
        assert!(f[[10, 9]] <= -2.9, "{}", f[[10, 9]]);
        assert!(frame_features(Array2::<f32>::zeros((0, 8)).view()).is_err());
        let mut nan = Array2::<f32>::zeros((5, 8));
        nan[[2, 3]] = f32::NAN;
        assert!(frame_features(nan.view()).is_err());
    }
}
