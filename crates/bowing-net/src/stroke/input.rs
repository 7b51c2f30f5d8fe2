//! The stroke network's per-frame input, made from the 30 fps × 128 mel dB spectrogram so
//! that it does not depend on the recording's level.
//!
//! * the 128 bands minus the recording's reference level (the 99th percentile of the frames'
//!   loudest band): a file 20 dB quieter gives the same values, down to the −80 dB floor the
//!   dB conversion clips at;
//! * the positive spectral flux (mean over bands of the rise since the previous frame, dB);
//! * the frame's loudest band relative to the reference (dB).
//!
//! Non-finite values become the floor. The network normalises every feature with the
//! training data's mean and standard deviation (stored with its weights).

use ndarray::{Array2, ArrayView2};

/// Features per frame: 128 bands, flux, level.
pub fn input_features(bands: usize) -> usize {
    bands + 2
}

/// dB below the reference treated as silence.
pub const FLOOR_DB: f32 = -80.0;

/// The lowest reference level (dB): a recording quieter than this (about −70 dBFS) is not
/// raised to full level, so silence stays silent.
pub const REFERENCE_FLOOR_DB: f32 = -30.0;

/// The recording's reference level: 99th percentile of the per-frame maximum (dB), at
/// least [`REFERENCE_FLOOR_DB`].
pub fn reference_level_db(mel_db: ArrayView2<f32>) -> f32 {
    let mut peaks: Vec<f32> = mel_db
        .rows()
        .into_iter()
        .filter_map(|r| r.iter().copied().filter(|v| v.is_finite()).reduce(f32::max))
        .collect();
    if peaks.is_empty() {
        return REFERENCE_FLOOR_DB;
    }
    let k = ((peaks.len() - 1) as f64 * 0.99).round() as usize;
    let (_, v, _) = peaks.select_nth_unstable_by(k, f32::total_cmp);
    v.max(REFERENCE_FLOOR_DB)
}

/// Bands on either side that a tonal peak is measured against.
const PEAK_SPAN: usize = 4;

/// How far the most prominent spectral peak of each frame stands above the bands
/// `PEAK_SPAN` (4) bins away on either side (dB), from a [`stroke_input`]: 25–45 dB for a bowed
/// note, about 8–13 dB for white, pink or brown noise.
pub fn tonal_prominence_db(input: &Array2<f32>) -> Vec<f32> {
    let bands = input.ncols().saturating_sub(2);
    input
        .rows()
        .into_iter()
        .map(|row| {
            (PEAK_SPAN..bands.saturating_sub(PEAK_SPAN))
                .map(|b| row[b] - 0.5 * (row[b - PEAK_SPAN] + row[b + PEAK_SPAN]))
                .fold(0.0f32, f32::max)
        })
        .collect()
}

/// The input of every frame (see the module docs): `(frames, bands + 2)`.
///
/// ```
/// let mel = ndarray::Array2::from_shape_fn((10, 4), |(t, b)| (t + b) as f32 - 10.0);
/// let quiet = mel.mapv(|v| v - 20.0);
/// let a = bowing_net::stroke::stroke_input(mel.view());
/// assert_eq!(a.dim(), (10, 6));
/// assert_eq!(a, bowing_net::stroke::stroke_input(quiet.view()));
/// ```
pub fn stroke_input(mel_db: ArrayView2<f32>) -> Array2<f32> {
    let (frames, bands) = mel_db.dim();
    let reference = reference_level_db(mel_db);
    let mut out = Array2::<f32>::zeros((frames, input_features(bands)));
    for t in 0..frames {
        for b in 0..bands {
            let v = mel_db[(t, b)];
            out[(t, b)] = if v.is_finite() {
                (v - reference).max(FLOOR_DB)
            } else {
                FLOOR_DB
            };
        }
    }
    if let Some(rows) = out.as_slice_mut() {
        fill_flux_and_level(rows, bands);
    }
    out
}

/// Writes the flux and level columns of input rows (`bands + 2` values per row, the bands
/// already set): the mean positive rise of the bands since the previous row (0 for the first)
/// and the loudest band. Used by [`stroke_input`] and by the training augmentation, which
/// changes the bands of a crop.
pub(crate) fn fill_flux_and_level(rows: &mut [f32], bands: usize) {
    let features = input_features(bands);
    for t in 0..rows.len() / features {
        let (before, here) = rows.split_at_mut(t * features);
        let row = &mut here[..features];
        let previous = t
            .checked_sub(1)
            .map(|p| &before[p * features..p * features + bands]);
        let mut flux = 0.0f32;
        let mut level = FLOOR_DB;
        for b in 0..bands {
            let v = row[b];
            level = level.max(v);
            if let Some(p) = previous {
                flux += (v - p[b]).max(0.0);
            }
        }
        row[bands] = flux / bands.max(1) as f32;
        row[bands + 1] = level;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gain_invariant_and_safe_on_bad_values() {
        let mel = Array2::from_shape_fn((50, 8), |(t, b)| ((t * 7 + b * 3) % 40) as f32 - 10.0);
        let loud = stroke_input(mel.view());
        let quiet = stroke_input(mel.mapv(|v| v - 19.0).view());
        assert_eq!(loud, quiet);
        let mut bad = mel.clone();
        bad[(3, 2)] = f32::NAN;
        bad[(4, 1)] = f32::INFINITY;
        assert!(stroke_input(bad.view()).iter().all(|v| v.is_finite()));
        let empty = Array2::<f32>::zeros((0, 8));
        assert_eq!(stroke_input(empty.view()).dim(), (0, 10));
        assert_eq!(
            reference_level_db(Array2::from_elem((3, 2), f32::NAN).view()),
            REFERENCE_FLOOR_DB
        );
        // Silence (every band at the dB floor) stays far below the sounding level.
        let silent = stroke_input(Array2::from_elem((5, 8), -100.0f32).view());
        assert!(silent.iter().take(8).all(|&v| v <= -70.0));
    }
}
