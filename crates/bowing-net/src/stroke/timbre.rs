//! Timbre augmentation for training the stroke network (feature `train`): each training crop
//! is heard through a random, smooth, fixed equaliser — a tilt across the bands and a few
//! broad resonances or notches — so that the network learns bow changes that do not depend on
//! one violin's body and recording chain. Violins it never heard differ from the training
//! violins mostly in such a fixed spectral envelope. The curve is
//! [`net_core::frames::random_eq_curve`]; [`equalise`] applies it to the stroke input.

use super::input::{fill_flux_and_level, FLOOR_DB};

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
    net_core::frames::equalise_bands(crop, features, bands, curve, FLOOR_DB, f32::INFINITY);
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
}
