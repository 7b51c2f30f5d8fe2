//! Peak picking and onset detection as `librosa.util.peak_pick` and
//! `librosa.onset.onset_detect`.

use serde::{Deserialize, Serialize};

/// Parameters of [`peak_pick`], in frames (`delta` in the signal's units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PeakPick {
    /// Frames before `n` in the maximum window.
    pub pre_max: usize,
    /// Frames after `n` in the maximum window (≥ 1; the window is `n − pre_max .. n + post_max`).
    pub post_max: usize,
    /// Frames before `n` in the mean window.
    pub pre_avg: usize,
    /// Frames after `n` in the mean window (≥ 1).
    pub post_avg: usize,
    /// Height above the local mean a peak needs.
    pub delta: f32,
    /// Frames to skip after a peak.
    pub wait: usize,
}

impl PeakPick {
    /// `onset_detect`'s defaults at `sample_rate_hz` and `hop_length`: 30 ms before for the
    /// maximum, 100 ms either side for the mean, wait 30 ms, delta 0.07 (of the normalised
    /// envelope).
    pub fn onset_defaults(sample_rate_hz: u32, hop_length: usize) -> PeakPick {
        let frames = |s: f64| (s * f64::from(sample_rate_hz) / hop_length as f64).floor() as usize;
        PeakPick {
            pre_max: frames(0.03),
            post_max: 1,
            pre_avg: frames(0.10),
            post_avg: frames(0.10) + 1,
            delta: 0.07,
            wait: frames(0.03),
        }
    }
}

/// Indices of the peaks of `x`: `x[n]` is the maximum of `x[n − pre_max .. n + post_max]`,
/// at least `delta` above the mean of `x[n − pre_avg .. n + post_avg]`, and at least `wait`
/// frames after the previous peak (librosa's algorithm, including its first-sample rule).
///
/// ```
/// use beat_track::{peak_pick, PeakPick};
/// let x = [0.0, 1.0, 0.0, 0.0, 0.5, 0.0, 0.9, 0.0];
/// let p = PeakPick { pre_max: 1, post_max: 2, pre_avg: 2, post_avg: 2, delta: 0.3, wait: 0 };
/// assert_eq!(peak_pick(&x, &p), vec![1, 4, 6]);
/// ```
pub fn peak_pick(x: &[f32], p: &PeakPick) -> Vec<usize> {
    let n_x = x.len();
    let mut peaks = Vec::new();
    if n_x == 0 {
        return peaks;
    }
    let post_max = p.post_max.max(1);
    let post_avg = p.post_avg.max(1);
    let max_of = |s: &[f32]| s.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    let mean_of = |s: &[f32]| s.iter().map(|&v| f64::from(v)).sum::<f64>() / s.len() as f64;
    let mut n = 1;
    if x[0] >= max_of(&x[..post_max.min(n_x)])
        && f64::from(x[0]) >= mean_of(&x[..post_avg.min(n_x)]) + f64::from(p.delta)
    {
        peaks.push(0);
        n = p.wait + 1;
    }
    while n < n_x {
        let maxn = max_of(&x[n.saturating_sub(p.pre_max)..(n + post_max).min(n_x)]);
        if x[n] != maxn {
            n += 1;
            continue;
        }
        let avgn = mean_of(&x[n.saturating_sub(p.pre_avg)..(n + post_avg).min(n_x)]);
        if f64::from(x[n]) < avgn + f64::from(p.delta) {
            n += 1;
            continue;
        }
        peaks.push(n);
        n += p.wait + 1;
    }
    peaks
}

/// Onset frames of an onset-strength curve as `librosa.onset.onset_detect` finds them:
/// normalise to [0, 1] (minus the minimum, over the maximum), then [`peak_pick`]. A flat or
/// empty curve has no onsets.
pub fn onset_detect(envelope: &[f32], peak: &PeakPick) -> Vec<usize> {
    let lo = envelope.iter().copied().fold(f32::INFINITY, f32::min);
    let mut x: Vec<f32> = envelope.iter().map(|v| v - lo).collect();
    let hi = x.iter().copied().fold(0.0f32, f32::max);
    if hi.is_nan() || hi <= 0.0 || x.iter().any(|v| !v.is_finite()) {
        return Vec::new();
    }
    let scale = hi + f32::MIN_POSITIVE;
    x.iter_mut().for_each(|v| *v /= scale);
    peak_pick(&x, peak)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_match_librosa_at_22050_hop_512() {
        let p = PeakPick::onset_defaults(22_050, 512);
        assert_eq!(
            (p.pre_max, p.post_max, p.pre_avg, p.post_avg, p.wait),
            (1, 1, 4, 5, 1)
        );
    }

    #[test]
    fn flat_curves_have_no_onsets() {
        let p = PeakPick::onset_defaults(22_050, 512);
        assert!(onset_detect(&[0.0; 100], &p).is_empty());
        assert!(onset_detect(&[], &p).is_empty());
    }
}
