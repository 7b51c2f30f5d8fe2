//! Timbre augmentation for training the stroke network (feature `train`): each training crop
//! is heard through a random, smooth, fixed equaliser — a tilt across the bands and a few
//! broad resonances or notches — so that the network learns bow changes that do not depend on
//! one violin's body and recording chain. Violins it never heard differ from the training
//! violins mostly in such a fixed spectral envelope.

use net_core::rng::Rng;

use super::input::{fill_flux_and_level, FLOOR_DB};

/// A random equaliser over `bands` mel bands, at most about `depth_db` deep: a tilt of up to
/// ±`depth_db`/2 from the lowest to the highest band, plus three Gaussian bumps of up to
/// ±`depth_db` each, 4–24 bands wide (standard deviation), centred anywhere.
///
/// ```
/// let mut rng = net_core::rng::Rng::new(3);
/// let curve = bowing_net::stroke::timbre::random_curve(&mut rng, 128, 6.0);
/// assert_eq!(curve.len(), 128);
/// assert!(curve.iter().all(|g| g.abs() <= 3.0 + 18.0));
/// assert!(bowing_net::stroke::timbre::random_curve(&mut rng, 128, 0.0).iter().all(|g| *g == 0.0));
/// ```
pub fn random_curve(rng: &mut Rng, bands: usize, depth_db: f32) -> Vec<f32> {
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

/// Applies `curve` to a crop of stroke-network input rows (`features` values per row: the
/// bands, then flux and level, as [`super::stroke_input`] makes them). Bands at the floor stay
/// there; the crop is shifted so that its loudest frame keeps its level (the input is relative
/// to the recording's loudest frames); flux and level are recomputed as
/// [`super::stroke_input`] computes them.
pub fn equalise(crop: &mut [f32], features: usize, curve: &[f32]) {
    let bands = features.saturating_sub(2);
    if bands == 0 || curve.len() != bands {
        return;
    }
    let loudest = |crop: &[f32]| {
        crop.chunks_exact(features)
            .flat_map(|row| row[..bands].iter().copied())
            .fold(FLOOR_DB, f32::max)
    };
    let before = loudest(crop);
    for row in crop.chunks_exact_mut(features) {
        for (v, g) in row[..bands].iter_mut().zip(curve) {
            if *v > FLOOR_DB {
                *v = (*v + g).max(FLOOR_DB);
            }
        }
    }
    let shift = loudest(crop) - before;
    for row in crop.chunks_exact_mut(features) {
        for v in row[..bands].iter_mut().filter(|v| **v > FLOOR_DB) {
            *v = (*v - shift).max(FLOOR_DB);
        }
    }
    fill_flux_and_level(crop, bands);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stroke::stroke_input;

    #[test]
    fn a_flat_curve_keeps_the_input_and_a_tilt_keeps_the_loudest_level() {
        let mel = ndarray::Array2::from_shape_fn((20, 16), |(t, b)| {
            -20.0 - (b as f32) - if t % 5 == 0 { 0.0 } else { 10.0 }
        });
        let input = stroke_input(mel.view());
        let mut flat: Vec<f32> = input.iter().copied().collect();
        equalise(&mut flat, 18, &[0.0; 16]);
        for (a, b) in flat.iter().zip(input.iter()) {
            assert!((a - b).abs() < 1e-4, "{a} {b}");
        }
        let tilt: Vec<f32> = (0..16).map(|b| b as f32 - 8.0).collect();
        let mut tilted: Vec<f32> = input.iter().copied().collect();
        equalise(&mut tilted, 18, &tilt);
        let level = |x: &[f32]| x.chunks(18).map(|r| r[17]).fold(f32::MIN, f32::max);
        assert!((level(&tilted) - level(&flat)).abs() < 1e-4);
        assert!(tilted.iter().all(|v| v.is_finite() && *v >= FLOOR_DB));
        // Floor bands stay at the floor.
        let mut quiet = vec![FLOOR_DB; 18 * 3];
        equalise(&mut quiet, 18, &tilt);
        assert!(quiet
            .chunks(18)
            .all(|r| r[..16].iter().all(|v| *v == FLOOR_DB)));
    }

    #[test]
    fn curves_are_seeded() {
        let a = random_curve(&mut Rng::new(9), 128, 6.0);
        let b = random_curve(&mut Rng::new(9), 128, 6.0);
        assert_eq!(a, b);
        assert!(a.iter().any(|g| g.abs() > 0.5));
    }
}
