//! The speed profile inside a stroke (step 5 of [`crate::bow`]'s algorithm): the bow eases in
//! and out at `reversal_speed` × cruise along smoothstep ramps.

use crate::bow_stroke::{BowPolicy, PlannedStroke};
use crate::geometry::smoothstep;

/// Share of the stroke covered at `u` ∈ [0, 1] under the eased speed profile.
fn eased(u: f64, e: f64, r: f64) -> f64 {
    // ∫₀ˣ smoothstep = x³ − x⁴/2.
    let ramp = |x: f64| x * x * x - 0.5 * x * x * x * x;
    let cum = |u: f64| -> f64 {
        if r <= 0.0 {
            return u;
        }
        if u <= r {
            e * u + (1.0 - e) * r * ramp(u / r)
        } else {
            e * u + (1.0 - e) * (0.5 * r + (u - r).min(1.0 - 2.0 * r))
        }
    };
    let total = e + (1.0 - e) * (1.0 - r);
    let u = u.clamp(0.0, 1.0);
    let value = if u <= 1.0 - r || r <= 0.0 {
        cum(u)
    } else {
        total - cum(1.0 - u)
    };
    if total > 0.0 {
        value / total
    } else {
        smoothstep(u)
    }
}

/// Bow position per frame of the planned `strokes` under the eased speed profile.
pub(crate) fn sample_strokes(
    strokes: &[PlannedStroke],
    frames: usize,
    policy: &BowPolicy,
) -> Vec<f32> {
    let mut positions = vec![0.0f32; frames];
    for s in strokes {
        let n = (s.end_frame - s.start_frame) as f64;
        let span = s.end_position - s.start_position;
        let end = s.end_frame.min(frames);
        for (k, slot) in positions[s.start_frame.min(end)..end]
            .iter_mut()
            .enumerate()
        {
            let share = eased(k as f64 / n, policy.reversal_speed, policy.ramp_fraction);
            *slot = (s.start_position + span * share) as f32;
        }
    }
    positions
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eased_profile_is_monotone_and_ends_at_one() {
        for (e, r) in [(0.25, 0.25), (0.0, 0.5), (1.0, 0.25), (0.3, 0.0)] {
            assert!(eased(0.0, e, r).abs() < 1e-12);
            assert!((eased(1.0, e, r) - 1.0).abs() < 1e-12);
            let mut prev = 0.0;
            for i in 1..=200 {
                let v = eased(i as f64 / 200.0, e, r);
                assert!(v >= prev - 1e-12, "not monotone at e={e} r={r}");
                prev = v;
            }
            // Symmetric: the second half mirrors the first.
            assert!((eased(0.3, e, r) + eased(0.7, e, r) - 1.0).abs() < 1e-12);
        }
    }
}
