//! Frame probabilities → bow-change frames: threshold, local maxima, minimum spacing.

use serde::{Deserialize, Serialize};

/// How probabilities are turned into change points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Decoder {
    /// A change needs at least this probability.
    pub threshold: f32,
    /// Two changes are at least this many frames apart (the more probable one wins).
    pub min_spacing_frames: usize,
}

impl Default for Decoder {
    fn default() -> Self {
        Self {
            threshold: 0.5,
            min_spacing_frames: 2,
        }
    }
}

impl Decoder {
    /// Change frames of `probs` (sorted): frames at or above the threshold that are local
    /// maxima (≥ the previous frame, > the next), accepted from the most probable down unless
    /// an accepted change is closer than the minimum spacing.
    ///
    /// ```
    /// use bowing_net::Decoder;
    /// let p = [0.1, 0.9, 0.7, 0.2, 0.6, 0.8, 0.1, 0.3];
    /// let d = Decoder { threshold: 0.5, min_spacing_frames: 2 };
    /// assert_eq!(d.pick(&p), vec![1, 5]);
    /// let d = Decoder { threshold: 0.5, min_spacing_frames: 5 };
    /// assert_eq!(d.pick(&p), vec![1]);
    /// ```
    pub fn pick(&self, probs: &[f32]) -> Vec<usize> {
        let n = probs.len();
        let mut candidates: Vec<usize> = (0..n)
            .filter(|&i| {
                let p = probs[i];
                p >= self.threshold
                    && (i == 0 || p >= probs[i - 1])
                    && (i + 1 == n || p > probs[i + 1])
            })
            .collect();
        candidates.sort_by(|&a, &b| probs[b].total_cmp(&probs[a]).then(a.cmp(&b)));
        let mut taken = std::collections::BTreeSet::new();
        let spacing = self.min_spacing_frames.max(1);
        for c in candidates {
            let lo = c.saturating_sub(spacing - 1);
            if taken.range(lo..c + spacing).next().is_none() {
                taken.insert(c);
            }
        }
        taken.into_iter().collect()
    }

    /// The picked changes of `probs` in fractional frames: each picked frame moved to the
    /// vertex of the parabola through its probability and its two neighbours' (at most half
    /// a frame either way; a frame at either end stays where it is). At 30 fps a frame is
    /// 33 ms, and the change rarely falls on a frame's centre.
    ///
    /// ```
    /// use bowing_net::Decoder;
    /// let p = [0.1, 0.6, 0.9, 0.8, 0.1];
    /// let d = Decoder { threshold: 0.5, min_spacing_frames: 2 };
    /// let f = d.pick_fractional(&p);
    /// assert_eq!(f.len(), 1);
    /// assert!(f[0] > 2.0 && f[0] < 2.5); // the right neighbour is the higher one
    /// ```
    pub fn pick_fractional(&self, probs: &[f32]) -> Vec<f64> {
        self.pick(probs)
            .into_iter()
            .map(|f| f as f64 + peak_offset_frames(probs, f))
            .collect()
    }
}

/// Offset (frames, within ±0.5) of the vertex of the parabola through `probs[f - 1..=f + 1]`
/// from `f`; 0 at the ends or where the three values are not a peak.
fn peak_offset_frames(probs: &[f32], f: usize) -> f64 {
    let (Some(&a), Some(&b), Some(&c)) = (
        f.checked_sub(1).and_then(|i| probs.get(i)),
        probs.get(f),
        probs.get(f + 1),
    ) else {
        return 0.0;
    };
    let (a, b, c) = (f64::from(a), f64::from(b), f64::from(c));
    let curvature = a - 2.0 * b + c;
    if curvature >= 0.0 || !curvature.is_finite() {
        return 0.0;
    }
    (0.5 * (a - c) / curvature).clamp(-0.5, 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peak_offsets_follow_the_higher_neighbour_and_stay_within_half_a_frame() {
        let symmetric = [0.2, 0.9, 0.2];
        assert_eq!(peak_offset_frames(&symmetric, 1), 0.0);
        let left = [0.8, 0.9, 0.2];
        let o = peak_offset_frames(&left, 1);
        assert!((-0.5..0.0).contains(&o), "{o}");
        // A plateau (equal neighbour) lands halfway, never beyond.
        assert_eq!(peak_offset_frames(&[0.2, 0.9, 0.9], 1), 0.5);
        // Ends and flat or non-finite values stay put.
        assert_eq!(peak_offset_frames(&left, 0), 0.0);
        assert_eq!(peak_offset_frames(&left, 2), 0.0);
        assert_eq!(peak_offset_frames(&[0.5, 0.5, 0.5], 1), 0.0);
        assert_eq!(peak_offset_frames(&[f32::NAN, 0.9, 0.2], 1), 0.0);
    }
}
