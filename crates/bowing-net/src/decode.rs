//! Frame probabilities → bow-change frames: threshold, local maxima, minimum spacing, and
//! optionally the splitting of long runs of high probability ([`RunSplit`]).

use serde::{Deserialize, Serialize};

/// How probabilities are turned into change points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Decoder {
    /// A change needs at least this probability.
    pub threshold: f32,
    /// Two changes are at least this many frames apart (the more probable one wins).
    pub min_spacing_frames: usize,
    /// Long runs of frames at or above the threshold hold several changes (`None`: one
    /// per local maximum only). Absent from decoders stored before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run_split: Option<RunSplit>,
}

impl Default for Decoder {
    fn default() -> Self {
        Self {
            threshold: 0.5,
            min_spacing_frames: 2,
            run_split: None,
        }
    }
}

/// Fast strokes: at 30 fps the peaks of bow changes 2–3 frames apart merge into one run of
/// frames at or above the threshold with a single maximum, and a run's length tells how many
/// changes it holds. A maximal run of `L` frames holding fewer picks than
/// `n = max(1, ⌊(L + offset_frames) / frames_per_change⌋)` gets `n` changes evenly spaced
/// over it instead.
///
/// ```
/// use bowing_net::{Decoder, RunSplit};
/// // One run of 9 frames with one maximum: three changes 3 frames apart.
/// let p = [0.1, 0.7, 0.8, 0.8, 0.9, 0.9, 0.8, 0.8, 0.75, 0.7, 0.1];
/// let plain = Decoder { threshold: 0.65, min_spacing_frames: 3, run_split: None };
/// assert_eq!(plain.pick(&p).len(), 1);
/// let split = RunSplit { frames_per_change: 3.0, offset_frames: 0.0 };
/// let d = Decoder { run_split: Some(split), ..plain };
/// assert_eq!(d.pick_fractional(&p), vec![2.0, 5.0, 8.0]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RunSplit {
    /// Frames of a run per change it holds.
    pub frames_per_change: f32,
    /// Added to the run's length before dividing, frames.
    pub offset_frames: f32,
}

impl RunSplit {
    /// Changes a run of `run_frames` frames holds: at least one, at most one per frame
    /// (whatever settings a weights file carries).
    pub fn changes_in(&self, run_frames: usize) -> usize {
        let n = (run_frames as f32 + self.offset_frames) / self.frames_per_change.max(0.5);
        if n.is_finite() {
            (n.floor() as usize).clamp(1, run_frames.max(1))
        } else {
            1
        }
    }

    /// `picks` (fractional frames, sorted) with every run of `probs` at or above
    /// `threshold` that holds fewer of them than [`RunSplit::changes_in`] its length given
    /// evenly spaced changes instead.
    pub fn apply(&self, probs: &[f32], threshold: f32, picks: Vec<f64>) -> Vec<f64> {
        let mut out = Vec::with_capacity(picks.len());
        let mut next_pick = 0;
        // A NaN frame is outside every run (it must not stall the scan).
        let high = |p: f32| p >= threshold;
        let mut i = 0;
        while i < probs.len() {
            if !high(probs[i]) {
                i += 1;
                continue;
            }
            let start = i;
            while i < probs.len() && high(probs[i]) {
                i += 1;
            }
            // Picks before this run, then those inside it.
            let lo = start as f64 - 0.5;
            let hi = i as f64 - 0.5;
            while next_pick < picks.len() && picks[next_pick] < lo {
                out.push(picks[next_pick]);
                next_pick += 1;
            }
            let first_inside = next_pick;
            while next_pick < picks.len() && picks[next_pick] <= hi {
                next_pick += 1;
            }
            let inside = &picks[first_inside..next_pick];
            let n = self.changes_in(i - start);
            if inside.len() >= n {
                out.extend_from_slice(inside);
            } else {
                let len = (i - start) as f64;
                out.extend((0..n).map(|j| lo + len * (j as f64 + 0.5) / n as f64));
            }
        }
        out.extend_from_slice(&picks[next_pick..]);
        out
    }
}

impl Decoder {
    /// Change frames of `probs` (sorted): frames at or above the threshold that are local
    /// maxima (≥ the previous frame, > the next), accepted from the most probable down unless
    /// an accepted change is closer than the minimum spacing; with a [`RunSplit`], the
    /// frames of [`Decoder::pick_fractional`] rounded.
    ///
    /// ```
    /// use bowing_net::Decoder;
    /// let p = [0.1, 0.9, 0.7, 0.2, 0.6, 0.8, 0.1, 0.3];
    /// let d = Decoder { threshold: 0.5, min_spacing_frames: 2, run_split: None };
    /// assert_eq!(d.pick(&p), vec![1, 5]);
    /// let d = Decoder { threshold: 0.5, min_spacing_frames: 5, run_split: None };
    /// assert_eq!(d.pick(&p), vec![1]);
    /// ```
    pub fn pick(&self, probs: &[f32]) -> Vec<usize> {
        if self.run_split.is_none() {
            return self.peaks(probs);
        }
        let mut frames: Vec<usize> = self
            .pick_fractional(probs)
            .into_iter()
            .map(|f| f.round().max(0.0) as usize)
            .collect();
        frames.dedup();
        frames
    }

    /// The local maxima of [`Decoder::pick`], without the run split.
    fn peaks(&self, probs: &[f32]) -> Vec<usize> {
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
    /// let d = Decoder { threshold: 0.5, min_spacing_frames: 2, run_split: None };
    /// let f = d.pick_fractional(&p);
    /// assert_eq!(f.len(), 1);
    /// assert!(f[0] > 2.0 && f[0] < 2.5); // the right neighbour is the higher one
    /// ```
    pub fn pick_fractional(&self, probs: &[f32]) -> Vec<f64> {
        let picks: Vec<f64> = self
            .peaks(probs)
            .into_iter()
            .map(|f| f as f64 + peak_offset_frames(probs, f))
            .collect();
        match self.run_split {
            Some(split) => split.apply(probs, self.threshold, picks),
            None => picks,
        }
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

    fn split(frames_per_change: f32, offset_frames: f32) -> Decoder {
        Decoder {
            threshold: 0.5,
            min_spacing_frames: 3,
            run_split: Some(RunSplit {
                frames_per_change,
                offset_frames,
            }),
        }
    }

    #[test]
    fn run_split_counts_changes_by_run_length() {
        let s = RunSplit {
            frames_per_change: 3.0,
            offset_frames: 1.0,
        };
        let counts: Vec<usize> = (1..=12).map(|l| s.changes_in(l)).collect();
        assert_eq!(counts, vec![1, 1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4]);
        // Degenerate settings still give at least one change and at most one per frame.
        let huge = RunSplit {
            frames_per_change: 1.0,
            offset_frames: 1e30,
        };
        assert_eq!(huge.changes_in(7), 7);
        let odd = RunSplit {
            frames_per_change: f32::NAN,
            offset_frames: -100.0,
        };
        assert_eq!(odd.changes_in(5), 1);
    }

    #[test]
    fn run_split_keeps_runs_with_enough_peaks_and_short_runs() {
        // Two separate peaks in one run of 6 frames: already two changes, kept as found.
        let p = [0.1, 0.9, 0.6, 0.55, 0.6, 0.9, 0.6, 0.1];
        let d = split(3.0, 0.0);
        let plain = Decoder {
            run_split: None,
            ..d
        };
        assert_eq!(d.pick_fractional(&p), plain.pick_fractional(&p));
        // A short run is one change wherever its peak is.
        let q = [0.1, 0.6, 0.9, 0.1, 0.1, 0.1];
        assert_eq!(d.pick(&q), vec![2]);
    }

    #[test]
    fn run_split_places_changes_evenly_and_leaves_other_runs_alone() {
        // A run of 6 frames (1..=6) with one maximum, then a lone peak at 9.
        let p = [0.1, 0.6, 0.7, 0.8, 0.9, 0.7, 0.6, 0.1, 0.2, 0.9, 0.1];
        let d = split(3.0, 0.0);
        assert_eq!(d.pick(&p), vec![2, 5, 9]);
        let f = d.pick_fractional(&p);
        assert_eq!(&f[..2], &[2.0, 5.0]);
        assert!((f[2] - 9.0).abs() <= 0.5);
    }

    #[test]
    fn run_split_survives_empty_nan_and_edge_runs() {
        let d = split(2.5, 1.0);
        assert!(d.pick(&[]).is_empty());
        assert!(d.pick_fractional(&[f32::NAN; 8]).is_empty());
        // A run touching both ends of the recording.
        let all_high = [0.9f32; 9];
        let f = d.pick_fractional(&all_high);
        assert_eq!(f.len(), 4);
        assert!(f.iter().all(|&x| (-0.5..8.5).contains(&x)), "{f:?}");
        assert!(f.windows(2).all(|w| w[0] < w[1]));
        // NaN frames split a run instead of stalling the scan.
        let p = [0.9, 0.9, f32::NAN, 0.9, 0.9, 0.9, 0.9, 0.9, 0.9];
        let picks = d.pick(&p);
        assert!(!picks.is_empty() && picks.windows(2).all(|w| w[0] < w[1]));
    }

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
