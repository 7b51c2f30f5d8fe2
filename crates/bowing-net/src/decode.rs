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
}

/// The decoder (threshold 0.2–0.9, spacing 2–4 frames) with the best F1 at ±2 frames.
pub fn tune_decoder(probs: &[Vec<f32>], val: &[crate::data::Recording]) -> (Decoder, f64) {
    let mut best = (Decoder::default(), -1.0);
    for spacing in 2..=4 {
        for k in 0..=14 {
            let d = Decoder {
                threshold: 0.2 + 0.05 * k as f32,
                min_spacing_frames: spacing,
            };
            let mut c = crate::metrics::Counts::default();
            for (p, r) in probs.iter().zip(val) {
                c.add(&crate::metrics::match_events(&d.pick(p), &r.changes, 2));
            }
            if c.f1() > best.1 {
                best = (d, c.f1());
            }
        }
    }
    best
}
