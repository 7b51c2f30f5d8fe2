//! Checks and windowing of a `(frames, bands)` spectrogram as the networks take it: the input
//! checks every network runs before inference, and the copy of a run of frames (padded with
//! silence outside the recording) into a window buffer, and the mel band shift the training
//! loops use as a pitch/timbre augmentation.

use ndarray::ArrayView2;

use crate::rng::Rng;

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

/// Moves the first `bands` features of every frame of `input` (`width` features per frame)
/// up by `shift` bands (down when negative), repeating the edge band into the gap; the
/// features after the first `bands` (onset, pitch) are left alone. Nothing moves when
/// `shift` or `bands` is 0 or `bands > width`.
///
/// ```
/// // Two frames of 4 mel bands and 1 extra feature.
/// let mut x = [1.0f32, 2.0, 3.0, 4.0, 9.0, 5.0, 6.0, 7.0, 8.0, 9.5];
/// net_core::frames::shift_bands(&mut x, 5, 4, 1);
/// assert_eq!(x, [1.0, 1.0, 2.0, 3.0, 9.0, 5.0, 5.0, 6.0, 7.0, 9.5]);
/// ```
pub fn shift_bands(input: &mut [f32], width: usize, bands: usize, shift: i64) {
    if shift == 0 || bands == 0 || bands > width {
        return;
    }
    let mut row = vec![0.0f32; bands];
    let last = bands as i64 - 1;
    for frame in input.chunks_exact_mut(width) {
        row.copy_from_slice(&frame[..bands]);
        for (b, d) in frame[..bands].iter_mut().enumerate() {
            *d = row[(b as i64 - shift).clamp(0, last) as usize];
        }
    }
}

/// A random, smooth, fixed equaliser over `bands` mel bands, at most about `depth_db` deep: a
/// tilt of up to ±`depth_db`/2 from the lowest to the highest band, plus three Gaussian bumps
/// of up to ±`depth_db` each, 4–24 bands wide (standard deviation), centred anywhere. Training
/// crops heard through it stand for violins and recording chains the corpus lacks, which
/// differ from its violins mostly in such a fixed spectral envelope. A depth of 0 (or 0 bands)
/// gives a flat curve and draws nothing.
///
/// ```
/// let mut rng = net_core::rng::Rng::new(3);
/// let curve = net_core::frames::random_eq_curve(&mut rng, 128, 6.0);
/// assert_eq!(curve.len(), 128);
/// assert!(curve.iter().all(|g| g.abs() <= 3.0 + 18.0));
/// assert!(net_core::frames::random_eq_curve(&mut rng, 128, 0.0).iter().all(|g| *g == 0.0));
/// ```
pub fn random_eq_curve(rng: &mut Rng, bands: usize, depth_db: f32) -> Vec<f32> {
    let depth = f64::from(depth_db.max(0.0));
    let mut curve = vec![0.0f32; bands];
    if depth == 0.0 || bands == 0 {
        return curve;
    }
    let tilt = rng.uniform(-0.5, 0.5) * depth;
    let span = (bands.max(2) - 1) as f64;
    let bumps: Vec<(f64, f64, f64)> = (0..3)
        .map(|_| {
            let gain = rng.uniform(-1.0, 1.0) * depth;
            let centre = rng.uniform(0.0, bands as f64);
            let width = rng.uniform(4.0, 24.0);
            (gain, centre, width)
        })
        .collect();
    for (b, g) in curve.iter_mut().enumerate() {
        let x = b as f64;
        let mut v = tilt * (2.0 * x / span - 1.0);
        for (gain, centre, width) in &bumps {
            let z = (x - centre) / width;
            v += gain * (-0.5 * z * z).exp();
        }
        *g = v as f32;
    }
    curve
}

/// Hears frames through a fixed equaliser: adds `curve` (dB, one value per band) to the first
/// `bands` values of every frame of `input` (`width` values per frame), leaving values at or
/// below `floor_db` (silence, clipped) where they are, then moves every band above the floor
/// by one amount so that the loudest value keeps its level (network inputs are relative to a
/// recording's loudest frames); values stay within `floor_db..=ceiling_db`. The features after
/// the first `bands` are the caller's to recompute. Nothing happens when `curve` does not have
/// `bands` values, `bands` is 0 or more than `width`, or the floor is not below the ceiling.
///
/// ```
/// // Two frames of 3 bands and 1 extra feature; the floor is −80 dB.
/// let mut x = [-10.0f32, -20.0, -80.0, 7.0, -30.0, -5.0, -80.0, 7.0];
/// net_core::frames::equalise_bands(&mut x, 4, 3, &[0.0, 10.0, 6.0], -80.0, 80.0);
/// assert_eq!(x, [-20.0, -20.0, -80.0, 7.0, -40.0, -5.0, -80.0, 7.0]);
/// ```
pub fn equalise_bands(
    input: &mut [f32],
    width: usize,
    bands: usize,
    curve: &[f32],
    floor_db: f32,
    ceiling_db: f32,
) {
    if bands == 0
        || bands > width
        || curve.len() != bands
        || floor_db.partial_cmp(&ceiling_db) != Some(std::cmp::Ordering::Less)
    {
        return;
    }
    let loudest = |input: &[f32]| {
        input
            .chunks_exact(width)
            .flat_map(|row| row[..bands].iter().copied())
            .fold(floor_db, f32::max)
    };
    let before = loudest(input);
    for row in input.chunks_exact_mut(width) {
        for (v, g) in row[..bands].iter_mut().zip(curve) {
            if *v > floor_db {
                *v = (*v + g).clamp(floor_db, ceiling_db);
            }
        }
    }
    let shift = loudest(input) - before;
    for row in input.chunks_exact_mut(width) {
        for v in row[..bands].iter_mut().filter(|v| **v > floor_db) {
            *v = (*v - shift).clamp(floor_db, ceiling_db);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::shift_bands;
    use crate::rng::Rng;

    #[test]
    fn equalising_with_a_floor_above_the_ceiling_changes_nothing() {
        let mut x = [-10.0f32, -20.0, 7.0];
        super::equalise_bands(&mut x, 3, 2, &[1.0, 2.0], 0.0, -80.0);
        super::equalise_bands(&mut x, 3, 2, &[1.0, 2.0], f32::NAN, 80.0);
        assert_eq!(x, [-10.0, -20.0, 7.0]);
    }

    #[test]
    fn eq_curves_are_seeded() {
        let a = super::random_eq_curve(&mut Rng::new(9), 128, 6.0);
        let b = super::random_eq_curve(&mut Rng::new(9), 128, 6.0);
        assert_eq!(a, b);
        assert!(a.iter().any(|g| g.abs() > 0.5));
    }

    #[test]
    fn band_shift_moves_the_mel_and_not_the_extra_features() {
        // Two frames of 4 bands + 1 extra feature.
        let mut x = vec![1.0, 2.0, 3.0, 4.0, 9.0, 5.0, 6.0, 7.0, 8.0, 9.5];
        shift_bands(&mut x, 5, 4, 1);
        assert_eq!(x, vec![1.0, 1.0, 2.0, 3.0, 9.0, 5.0, 5.0, 6.0, 7.0, 9.5]);
        shift_bands(&mut x, 5, 4, -2);
        assert_eq!(x, vec![2.0, 3.0, 3.0, 3.0, 9.0, 6.0, 7.0, 7.0, 7.0, 9.5]);
        shift_bands(&mut x, 5, 6, 1); // more bands than the frame: untouched
        assert_eq!(x[0], 2.0);
    }

    #[test]
    fn band_shift_of_whole_rows_repeats_both_edges() {
        let mut x = vec![0.0, 1.0, 2.0, 3.0, 10.0, 11.0, 12.0, 13.0];
        shift_bands(&mut x, 4, 4, 1);
        assert_eq!(x, vec![0.0, 0.0, 1.0, 2.0, 10.0, 10.0, 11.0, 12.0]);
        shift_bands(&mut x, 4, 4, -2);
        assert_eq!(x, vec![1.0, 2.0, 2.0, 2.0, 11.0, 12.0, 12.0, 12.0]);
        shift_bands(&mut x, 4, 0, 3); // no bands: untouched
        assert_eq!(x[0], 1.0);
    }
}
