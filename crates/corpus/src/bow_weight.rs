//! Bow weight: the level of a bowed note follows where on the bow it is played.
//!
//! The bow presses hardest at the frog, where the hand holds it, and least at the tip, so
//! a stroke the player does not compensate gets softer as a down-bow travels from frog to
//! tip and louder as an up-bow travels back. Players compensate with the index finger,
//! some fully, most not quite; short strokes use little bow and change little. The corpus
//! models this as a level tilt over each stroke:
//!
//! `gain_dB(u) = tilt_dB · travel · (½ − u)` for a down-bow and `· (u − ½)` for an up-bow,
//!
//! with `u` the fraction of the stroke played, `travel = min(1, stroke length / `
//! [`FULL_BOW_S`]`)` the share of the bow it uses, and `tilt_dB` drawn per item uniformly
//! from 0 (full compensation) to [`MAX_TILT_DB`]. A down-bow ends at the tip where the
//! next up-bow starts, so the gain is continuous at a bow change; it is held through rests
//! and smoothed over [`SMOOTHING_S`].

use net_core::rng::Rng;
use performance::{BowDirection, BowStroke};

/// Largest tilt over a whole bow, dB.
pub const MAX_TILT_DB: f64 = 4.0;
/// A stroke this long (seconds) or longer travels the whole bow.
pub const FULL_BOW_S: f64 = 1.0;
/// Time constant of the gain's smoothing, seconds.
pub const SMOOTHING_S: f64 = 0.005;

/// Draws an item's tilt (dB over a whole bow).
pub fn draw_tilt_db(rng: &mut Rng) -> f64 {
    rng.uniform(0.0, MAX_TILT_DB)
}

/// The gain in dB at time `t_s` of a stroke (`t_s` inside it or past its end).
fn stroke_gain_db(stroke: &BowStroke, t_s: f64, tilt_db: f64) -> f64 {
    let length = (stroke.end_s - stroke.start_s).max(1e-6);
    let u = ((t_s - stroke.start_s) / length).clamp(0.0, 1.0);
    let travel = (length / FULL_BOW_S).min(1.0);
    let signed = match stroke.direction {
        BowDirection::Down => 0.5 - u,
        BowDirection::Up => u - 0.5,
    };
    tilt_db * travel * signed
}

/// Applies the bow-weight tilt of `strokes` (sorted by start) to `audio` at
/// `sample_rate_hz`. A tilt of 0, no strokes or no audio leave it unchanged.
///
/// ```
/// use corpus::bow_weight::apply_bow_weight;
/// use performance::{BowDirection, BowStroke};
/// let down = BowStroke { start_s: 0.0, end_s: 1.0, direction: BowDirection::Down, string: None };
/// let mut audio = vec![1.0f32; 1000];
/// apply_bow_weight(&mut audio, 1000, &[down], 4.0);
/// assert!(audio[50] > 1.1 && audio[950] < 0.9); // louder at the frog, softer at the tip
/// ```
pub fn apply_bow_weight(
    audio: &mut [f32],
    sample_rate_hz: u32,
    strokes: &[BowStroke],
    tilt_db: f64,
) {
    if tilt_db == 0.0 || strokes.is_empty() || audio.is_empty() || sample_rate_hz == 0 {
        return;
    }
    let sr = f64::from(sample_rate_hz);
    let alpha = 1.0 - (-1.0 / (SMOOTHING_S * sr)).exp();
    // 10^(dB/20) as one exp per sample.
    let db_to_ln = std::f64::consts::LN_10 / 20.0;
    let mut k = 0usize;
    let mut smoothed_db = stroke_gain_db(&strokes[0], strokes[0].start_s, tilt_db);
    for (i, sample) in audio.iter_mut().enumerate() {
        let t = i as f64 / sr;
        while k + 1 < strokes.len() && strokes[k + 1].start_s <= t {
            k += 1;
        }
        let target = stroke_gain_db(&strokes[k], t, tilt_db);
        smoothed_db += alpha * (target - smoothed_db);
        *sample *= (smoothed_db * db_to_ln).exp() as f32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stroke(start_s: f64, end_s: f64, direction: BowDirection) -> BowStroke {
        BowStroke {
            start_s,
            end_s,
            direction,
            string: None,
        }
    }

    #[test]
    fn down_bows_fade_up_bows_swell_and_changes_are_continuous() {
        let sr = 1000;
        let strokes = [
            stroke(0.0, 1.0, BowDirection::Down),
            stroke(1.0, 2.0, BowDirection::Up),
        ];
        let mut audio = vec![1.0f32; 2000];
        apply_bow_weight(&mut audio, sr, &strokes, 4.0);
        let db = |i: usize| 20.0 * f64::from(audio[i]).log10();
        assert!((db(100) - 1.6).abs() < 0.1, "{}", db(100));
        assert!((db(900) + 1.6).abs() < 0.1, "{}", db(900));
        assert!((db(1100) + 1.6).abs() < 0.1, "{}", db(1100));
        assert!((db(1900) - 1.6).abs() < 0.1, "{}", db(1900));
        let jump = audio
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0f32, f32::max);
        assert!(jump < 0.01, "{jump}");
    }

    #[test]
    fn short_strokes_and_zero_tilt_change_little() {
        let strokes = [stroke(0.0, 0.1, BowDirection::Down)];
        let mut audio = vec![1.0f32; 100];
        apply_bow_weight(&mut audio, 1000, &strokes, 4.0);
        assert!(audio.iter().all(|v| (v - 1.0).abs() < 0.03));
        let mut same = vec![0.5f32; 100];
        apply_bow_weight(&mut same, 1000, &strokes, 0.0);
        assert!(same.iter().all(|&v| v == 0.5));
        apply_bow_weight(&mut [], 1000, &strokes, 4.0);
    }
}
