//! Body expression (SPEC §7): torso tilt from arousal, head sway once per bar.
//!
//! * **Arousal at 30 fps**: the 2 Hz curve through a [`MonotoneCubic`] (C¹, no overshoot,
//!   the last value held), or 0 (neutral) when there is none.
//! * **Torso tilt** (arousal ↔ tilt r = −0.70): `lean_forward_deg − arousal ·
//!   lean_per_arousal_deg`, so the player leans back as arousal rises and forward when calm.
//! * **Head sway** (arousal ↔ head acceleration r = +0.75): one nod per bar, forward-most
//!   on each downbeat and back-most before the next one. A bar's mean arousal `m` sets the
//!   extent, from `sway_min_deg` (m = −1) to `sway_max_deg` (m = +1), and the speed: the
//!   forward swing takes `sway_calm_forward_share` of the bar when calm and
//!   `sway_excited_forward_share` when excited, so excited bars nod faster (higher head
//!   acceleration). Extents are interpolated smoothly between bar centres; the swing shape
//!   is a half cosine each way, so the head's velocity is continuous across bar lines.
//!   Without downbeats the bars are `default_bar_s` long from time 0; before the first and
//!   after the last downbeat the nearest bar length is repeated.
//! * **Weight shift**: the hips move sideways to one foot over a bar and back over the
//!   next (a half sine per bar, 8 mm calm … 20 mm excited), the pelvis rolling with them.

use crate::interp::MonotoneCubic;
use performance::Performance;

/// Tunables of the body rules (degrees, seconds).
#[derive(Debug, Clone, PartialEq)]
pub struct BodyConfig {
    /// Forward lean at neutral arousal.
    pub lean_forward_deg: f64,
    /// Change of lean per unit of arousal (more arousal leans back).
    pub lean_per_arousal_deg: f64,
    /// Head sway extent (each way) for a bar of arousal −1.
    pub sway_min_deg: f64,
    /// Head sway extent (each way) for a bar of arousal +1.
    pub sway_max_deg: f64,
    /// Share of a calm bar (arousal −1) spent swinging forward into the downbeat.
    pub sway_calm_forward_share: f64,
    /// Share of an excited bar (arousal +1) spent swinging forward into the downbeat.
    pub sway_excited_forward_share: f64,
    /// Bar length used when there are no downbeats.
    pub default_bar_s: f64,
}

impl Default for BodyConfig {
    fn default() -> Self {
        BodyConfig {
            lean_forward_deg: 2.0,
            lean_per_arousal_deg: 4.0,
            sway_min_deg: 1.5,
            sway_max_deg: 7.0,
            sway_calm_forward_share: 0.5,
            sway_excited_forward_share: 0.25,
            default_bar_s: 2.0,
        }
    }
}

impl BodyConfig {
    pub(crate) fn is_valid(&self) -> bool {
        let finite = [
            self.lean_forward_deg,
            self.lean_per_arousal_deg,
            self.sway_min_deg,
            self.sway_max_deg,
        ]
        .iter()
        .all(|v| v.is_finite());
        let share = |s: f64| s > 0.0 && s < 1.0;
        finite
            && share(self.sway_calm_forward_share)
            && share(self.sway_excited_forward_share)
            && self.default_bar_s.is_finite()
            && self.default_bar_s > 0.0
    }
}

/// Per-frame body angles.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyTrack {
    /// Arousal at each frame, in [-1, 1].
    pub arousal: Vec<f64>,
    /// Torso tilt, radians, positive forward.
    pub torso_pitch_rad: Vec<f64>,
    /// Head nod, radians, positive forward.
    pub head_pitch_rad: Vec<f64>,
    /// Weight shift: the hips' sideways displacement, metres (+ towards the player's left),
    /// from one foot to the other over each bar.
    pub hip_shift_m: Vec<f64>,
    /// Pelvis roll going with the weight shift, radians.
    pub hip_roll_rad: Vec<f64>,
    /// Bar lines used for the sway (seconds), covering the whole performance.
    pub bar_lines_s: Vec<f64>,
}

/// Weight shift each way for a calm (arousal −1) and an excited (+1) bar, metres.
const SHIFT_CALM_M: f64 = 0.008;
const SHIFT_EXCITED_M: f64 = 0.02;
/// Pelvis roll per metre of weight shift, radians.
const ROLL_PER_M: f64 = 1.2;

/// Bar lines covering `[0, duration_s]`: the downbeats, extended before and after by the
/// nearest bar length (or `default_bar_s`).
pub fn bar_lines(downbeats_s: &[f64], duration_s: f64, default_bar_s: f64) -> Vec<f64> {
    let mut lines = Vec::new();
    if downbeats_s.is_empty() {
        let mut t = 0.0;
        while t < duration_s {
            lines.push(t);
            t += default_bar_s;
        }
        lines.push(t);
        return lines;
    }
    let n = downbeats_s.len();
    let first_len = if n > 1 {
        downbeats_s[1] - downbeats_s[0]
    } else {
        default_bar_s
    };
    let last_len = if n > 1 {
        downbeats_s[n - 1] - downbeats_s[n - 2]
    } else {
        default_bar_s
    };
    let mut before = Vec::new();
    let mut t = downbeats_s[0];
    while t > 0.0 {
        t -= first_len;
        before.push(t);
    }
    lines.extend(before.into_iter().rev());
    lines.extend_from_slice(downbeats_s);
    let mut t = downbeats_s[n - 1];
    while t < duration_s {
        t += last_len;
        lines.push(t);
    }
    lines
}

/// Head swing shape at bar phase `u` ∈ [0, 1): +1 (forward) at 0, −1 (back) at
/// `1 − forward_share`, +1 again at 1; half cosines, zero slope at both extremes.
pub fn sway_shape(u: f64, forward_share: f64) -> f64 {
    let back_at = 1.0 - forward_share;
    if u <= back_at {
        (std::f64::consts::PI * u / back_at).cos()
    } else {
        -(std::f64::consts::PI * (u - back_at) / forward_share).cos()
    }
}

/// Computes the body angles for `frames` frames at `fps`.
pub fn body_track(perf: &Performance, fps: f64, frames: usize, cfg: &BodyConfig) -> BodyTrack {
    let mut arousal = vec![0.0; frames];
    if let Some(curve) = perf.arousal() {
        let values = curve.values.iter().map(|&v| f64::from(v)).collect();
        let interp = MonotoneCubic::uniform(0.0, 1.0 / curve.rate_hz, values);
        let mut cursor = 0;
        for (f, a) in arousal.iter_mut().enumerate() {
            *a = interp
                .eval_from(&mut cursor, f as f64 / fps)
                .clamp(-1.0, 1.0);
        }
    }
    let torso_pitch_rad = arousal
        .iter()
        .map(|a| (cfg.lean_forward_deg - a * cfg.lean_per_arousal_deg).to_radians())
        .collect();

    let lines = bar_lines(perf.downbeats_s(), perf.duration_s(), cfg.default_bar_s);
    let bars = lines.len().saturating_sub(1);
    let mut centres = Vec::with_capacity(bars);
    let mut extents = Vec::with_capacity(bars);
    let mut shares = Vec::with_capacity(bars);
    for b in 0..bars {
        let (start, end) = (lines[b], lines[b + 1]);
        let lo = ((start * fps).ceil().max(0.0) as usize).min(frames);
        let hi = ((end * fps).ceil().max(0.0) as usize).min(frames);
        let mean = if hi > lo {
            arousal[lo..hi].iter().sum::<f64>() / (hi - lo) as f64
        } else {
            let mid = ((0.5 * (start + end) * fps) as usize).min(frames.saturating_sub(1));
            arousal.get(mid).copied().unwrap_or(0.0)
        };
        let excitement = (mean + 1.0) / 2.0;
        centres.push(0.5 * (start + end));
        extents.push(
            (cfg.sway_min_deg + (cfg.sway_max_deg - cfg.sway_min_deg) * excitement).to_radians(),
        );
        shares.push(
            cfg.sway_calm_forward_share
                + (cfg.sway_excited_forward_share - cfg.sway_calm_forward_share) * excitement,
        );
    }
    let extent = MonotoneCubic::new(centres, extents);
    let mut head_pitch_rad = vec![0.0; frames];
    let mut hip_shift_m = vec![0.0; frames];
    let (mut bar, mut cursor) = (0usize, 0usize);
    for (f, h) in head_pitch_rad.iter_mut().enumerate() {
        let t = f as f64 / fps;
        while bar + 1 < bars && lines[bar + 1] <= t {
            bar += 1;
        }
        if bars == 0 {
            break;
        }
        let (start, end) = (lines[bar], lines[bar + 1]);
        let u = ((t - start) / (end - start)).clamp(0.0, 1.0);
        let e = extent.eval_from(&mut cursor, t);
        *h = e * sway_shape(u, shares[bar]);
        // Weight moves to one foot over a bar and back over the next (zero at bar lines).
        let excitement = ((e.to_degrees() - cfg.sway_min_deg)
            / (cfg.sway_max_deg - cfg.sway_min_deg).max(1e-9))
        .clamp(0.0, 1.0);
        let amplitude = SHIFT_CALM_M + (SHIFT_EXCITED_M - SHIFT_CALM_M) * excitement;
        let sign = if bar % 2 == 0 { 1.0 } else { -1.0 };
        hip_shift_m[f] = sign * amplitude * (std::f64::consts::PI * u).sin();
    }
    let hip_roll_rad = hip_shift_m.iter().map(|s| s * ROLL_PER_M).collect();
    BodyTrack {
        arousal,
        torso_pitch_rad,
        head_pitch_rad,
        hip_shift_m,
        hip_roll_rad,
        bar_lines_s: lines,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bar_lines_extend_the_downbeats() {
        assert_eq!(bar_lines(&[], 5.0, 2.0), vec![0.0, 2.0, 4.0, 6.0]);
        assert_eq!(
            bar_lines(&[1.0, 3.0], 6.0, 2.0),
            vec![-1.0, 1.0, 3.0, 5.0, 7.0]
        );
        assert_eq!(bar_lines(&[0.0], 1.0, 2.0), vec![0.0, 2.0]);
    }

    #[test]
    fn sway_shape_is_forward_on_the_downbeat_and_smooth() {
        for share in [0.25, 0.5] {
            assert_eq!(sway_shape(0.0, share), 1.0);
            assert!((sway_shape(1.0 - share, share) + 1.0).abs() < 1e-12);
            assert!((sway_shape(1.0, share) - 1.0).abs() < 1e-12);
            let back = 1.0 - share;
            let left = (sway_shape(back, share) - sway_shape(back - 1e-6, share)) / 1e-6;
            let right = (sway_shape(back + 1e-6, share) - sway_shape(back, share)) / 1e-6;
            assert!(left.abs() < 1e-4 && right.abs() < 1e-4);
        }
    }
}
