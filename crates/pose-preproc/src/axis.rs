//! The bowing arm, the performer's size and the bow axis, found in the data (SPEC §3).
//!
//! * **Bow axis.** The bowing wrist relative to the neck is a point that runs back and forth
//!   along the bow. Over a sliding window (`axis_window_s`, a few seconds, centred on each
//!   frame) the 2×2 covariance of that point gives the principal direction of its motion;
//!   the wrist's coordinate along that direction is the track the rule labels. The direction
//!   is re-estimated at every frame (with prefix sums, so the cost does not depend on the
//!   window) and kept continuous: the doubled angle is unwrapped before halving, so the axis
//!   never flips sign between frames. Any camera yaw or roll works; a camera that sees the
//!   stroke head-on (the axis pointing at the lens) leaves too little motion for any rule.
//! * **Bowing arm.** The arm whose wrist moves most along a line relative to the neck: its
//!   score is the clip's mean of `√λ₁ − √λ₂` of the windowed covariance (the stroke's
//!   amplitude minus the scatter across it). The fingering hand, which stays near the
//!   violin's neck, scores far lower. Mirrored videos and left-handed players get the left
//!   arm.
//! * **Size.** The median over frames of the torso length (neck to the hips' midpoint); when
//!   the hips are unusable, the shoulder width. Thresholds are stated in this unit, so the
//!   camera's distance and the video's resolution do not matter.

use serde::{Deserialize, Serialize};
use skeleton::{Joint, Motion};

use crate::error::{PosePreprocError, Result};

/// Which arm bows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Arm {
    /// The (pose estimator's) right arm.
    Right,
    /// The left arm: a mirrored video or a left-handed player.
    Left,
}

impl Arm {
    /// The arm's wrist.
    pub fn wrist(self) -> Joint {
        match self {
            Arm::Right => Joint::RWrist,
            Arm::Left => Joint::LWrist,
        }
    }

    /// `"right"` or `"left"`.
    pub fn name(self) -> &'static str {
        match self {
            Arm::Right => "right",
            Arm::Left => "left",
        }
    }
}

/// Sliding-window principal axes of a 2-D track.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowedAxis {
    /// Unit direction `(x, y)` of the principal axis per frame, continuous over time.
    pub direction: Vec<[f64; 2]>,
    /// `√λ₁` per frame: the standard deviation along the axis, pixels.
    pub along: Vec<f64>,
    /// `√λ₂` per frame: the standard deviation across the axis, pixels.
    pub across: Vec<f64>,
}

impl WindowedAxis {
    /// Linearity per frame in `[0, 1]`: `(λ₁ − λ₂)/(λ₁ + λ₂)`, 0 when nothing moves.
    pub fn linearity(&self) -> Vec<f64> {
        self.along
            .iter()
            .zip(&self.across)
            .map(|(a, c)| {
                let (l1, l2) = (a * a, c * c);
                if l1 + l2 > 0.0 {
                    (l1 - l2) / (l1 + l2)
                } else {
                    0.0
                }
            })
            .collect()
    }
}

/// Principal axis of `points` over a centred window of `window` frames (clamped at the ends).
pub fn windowed_axis(points: &[[f64; 2]], window: usize) -> WindowedAxis {
    let n = points.len();
    let half = window.max(1) / 2;
    // Prefix sums of x, y, xx, xy, yy (relative to the first point, for precision).
    let origin = points.first().copied().unwrap_or([0.0, 0.0]);
    let mut prefix = Vec::with_capacity(n + 1);
    prefix.push([0.0f64; 5]);
    for p in points {
        let (x, y) = (p[0] - origin[0], p[1] - origin[1]);
        let last = prefix[prefix.len() - 1];
        prefix.push([
            last[0] + x,
            last[1] + y,
            last[2] + x * x,
            last[3] + x * y,
            last[4] + y * y,
        ]);
    }
    let mut out = WindowedAxis {
        direction: Vec::with_capacity(n),
        along: Vec::with_capacity(n),
        across: Vec::with_capacity(n),
    };
    let mut last_doubled: Option<f64> = None;
    for t in 0..n {
        let (a, b) = (t.saturating_sub(half), (t + half + 1).min(n));
        let m = (b - a) as f64;
        let s: [f64; 5] = std::array::from_fn(|k| (prefix[b][k] - prefix[a][k]) / m);
        let sxx = (s[2] - s[0] * s[0]).max(0.0);
        let syy = (s[4] - s[1] * s[1]).max(0.0);
        let sxy = s[3] - s[0] * s[1];
        let mut doubled = (2.0 * sxy).atan2(sxx - syy);
        if let Some(prev) = last_doubled {
            let tau = std::f64::consts::TAU;
            doubled += tau * ((prev - doubled) / tau).round();
        }
        last_doubled = Some(doubled);
        let angle = 0.5 * doubled;
        let mean = 0.5 * (sxx + syy);
        let spread = (0.25 * (sxx - syy).powi(2) + sxy * sxy).sqrt();
        out.direction.push([angle.cos(), angle.sin()]);
        out.along.push((mean + spread).max(0.0).sqrt());
        out.across.push((mean - spread).max(0.0).sqrt());
    }
    out
}

/// A joint's `(x, y)` track as f64.
fn track(motion: &Motion, joint: Joint) -> Vec<[f64; 2]> {
    motion
        .joint(joint)
        .rows()
        .into_iter()
        .map(|r| [f64::from(r[0]), f64::from(r[1])])
        .collect()
}

/// The wrist of `arm` relative to the neck, per frame.
pub fn wrist_relative_to_neck(motion: &Motion, arm: Arm) -> Vec<[f64; 2]> {
    let neck = track(motion, Joint::Neck);
    track(motion, arm.wrist())
        .into_iter()
        .zip(neck)
        .map(|(w, n)| [w[0] - n[0], w[1] - n[1]])
        .collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return 0.0;
    }
    let mid = v.len() / 2;
    v.select_nth_unstable_by(mid, f64::total_cmp);
    v[mid]
}

/// The performer's size in pixels: the median torso length (neck to the hips' midpoint), or
/// the median shoulder width when that is under 1 px. Fails when both are under 1 px.
pub fn performer_size_px(motion: &Motion) -> Result<f64> {
    let neck = track(motion, Joint::Neck);
    let (rh, lh) = (track(motion, Joint::RHip), track(motion, Joint::LHip));
    let torso: Vec<f64> = (0..neck.len())
        .map(|t| {
            let hx = 0.5 * (rh[t][0] + lh[t][0]);
            let hy = 0.5 * (rh[t][1] + lh[t][1]);
            (neck[t][0] - hx).hypot(neck[t][1] - hy)
        })
        .collect();
    let size = median(torso);
    if size >= 1.0 {
        return Ok(size);
    }
    let (rs, ls) = (
        track(motion, Joint::RShoulder),
        track(motion, Joint::LShoulder),
    );
    let width = median(
        rs.iter()
            .zip(&ls)
            .map(|(r, l)| (r[0] - l[0]).hypot(r[1] - l[1]))
            .collect(),
    );
    if width >= 1.0 {
        return Ok(width);
    }
    Err(PosePreprocError::NoSize { torso_px: size })
}

/// How strongly an arm's wrist moves along a line relative to the neck: the mean over frames
/// of `√λ₁ − √λ₂` of the windowed covariance, pixels.
pub fn bowing_score(axis: &WindowedAxis) -> f64 {
    if axis.along.is_empty() {
        return 0.0;
    }
    axis.along
        .iter()
        .zip(&axis.across)
        .map(|(a, c)| a - c)
        .sum::<f64>()
        / axis.along.len() as f64
}

/// The bowing arm of `motion` and both arms' scores `[right, left]` (see [`bowing_score`]),
/// with the windowed axes of the chosen arm.
pub fn find_bow_arm(motion: &Motion, window: usize) -> (Arm, [f64; 2], WindowedAxis) {
    let right = windowed_axis(&wrist_relative_to_neck(motion, Arm::Right), window);
    let left = windowed_axis(&wrist_relative_to_neck(motion, Arm::Left), window);
    let scores = [bowing_score(&right), bowing_score(&left)];
    if scores[1] > scores[0] {
        (Arm::Left, scores, left)
    } else {
        (Arm::Right, scores, right)
    }
}

/// The wrist's coordinate along the (per-frame) axis, relative to the neck, pixels.
pub fn project(points: &[[f64; 2]], axis: &WindowedAxis) -> Vec<f64> {
    points
        .iter()
        .zip(&axis.direction)
        .map(|(p, d)| p[0] * d[0] + p[1] * d[1])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_follows_a_rotating_line_without_flipping() {
        // Back and forth along a direction that turns slowly from 30° to 100°.
        let n = 600;
        let pts: Vec<[f64; 2]> = (0..n)
            .map(|t| {
                let ang = (30.0 + 70.0 * t as f64 / n as f64).to_radians();
                let s = 50.0 * (t as f64 / 7.0).sin();
                [s * ang.cos() + 3.0, s * ang.sin() - 2.0]
            })
            .collect();
        let ax = windowed_axis(&pts, 90);
        for w in ax.direction.windows(2) {
            assert!(w[0][0] * w[1][0] + w[0][1] * w[1][1] > 0.99);
        }
        let mid = ax.direction[300];
        let want = 65.0f64.to_radians();
        assert!((mid[0] * want.cos() + mid[1] * want.sin()).abs() > 0.99);
        assert!(ax.linearity()[300] > 0.95);
    }

    #[test]
    fn a_still_track_has_zero_linearity() {
        let ax = windowed_axis(&[[1.0, 1.0]; 20], 9);
        assert!(ax.linearity().iter().all(|&l| l == 0.0));
        assert_eq!(bowing_score(&ax), 0.0);
    }
}
