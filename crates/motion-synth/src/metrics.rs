//! Plausibility metrics of a synthesised motion (SPEC §10).

use ndarray::{Array3, Axis};
use serde::Serialize;
use skeleton::Motion;

use crate::contact;
use crate::synth::Synthesis;
use performance::Performance;

/// Share of frames whose bow position lies outside [0, 1] (0 for the planner by
/// construction; the original rule taken literally drifts, see [`crate::bow::plan_naive`]).
///
/// ```
/// assert_eq!(motion_synth::metrics::bow_range_violations(&[0.0, 0.5, 1.2, -0.1]), 0.5);
/// ```
pub fn bow_range_violations(positions: &[f32]) -> f64 {
    if positions.is_empty() {
        return 0.0;
    }
    let out = positions
        .iter()
        .filter(|p| !(0.0..=1.0).contains(*p))
        .count();
    out as f64 / positions.len() as f64
}

/// Largest coefficient of variation of a bone's length over time (3-D when present).
pub fn bone_length_variation(motion: &Motion) -> f32 {
    motion.max_bone_length_cv()
}

/// Mean joint acceleration of the 2-D track, pixels / frame².
pub fn jitter(motion: &Motion) -> f32 {
    motion.jitter()
}

/// Summed speed of all joints per frame (`speed[t] = Σ |p[t+1] − p[t]|`, the last frame
/// repeating the one before), of a `(T, J, D)` track.
pub fn summed_joint_speed(track: &Array3<f32>) -> Vec<f64> {
    let t = track.len_of(Axis(0));
    let mut speed = vec![0.0; t];
    for (f, slot) in speed.iter_mut().enumerate().take(t.saturating_sub(1)) {
        let (a, b) = (
            track.index_axis(Axis(0), f),
            track.index_axis(Axis(0), f + 1),
        );
        *slot = a
            .rows()
            .into_iter()
            .zip(b.rows())
            .map(|(p, q)| {
                p.iter()
                    .zip(q.iter())
                    .map(|(x, y)| f64::from(y - x).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .sum();
    }
    if t >= 2 {
        speed[t - 1] = speed[t - 2];
    }
    speed
}

/// Beat alignment score in [0, 1] (as in music-to-dance work): for every beat inside the
/// motion, `exp(−d² / (2σ²))` with `d` the distance in frames from the beat to the nearest
/// local minimum of the summed joint speed (3-D when present), averaged over beats. `None`
/// without beats in range; 0 when the motion has no speed minimum.
pub fn beat_alignment(motion: &Motion, beats_s: &[f64], sigma_frames: f64) -> Option<f64> {
    let track = motion.frames_3d().unwrap_or(motion.frames());
    let speed = summed_joint_speed(track);
    let minima: Vec<f64> = (1..speed.len().saturating_sub(1))
        .filter(|&i| speed[i] < speed[i - 1] && speed[i] <= speed[i + 1])
        .map(|i| i as f64)
        .collect();
    let last = motion.len() as f64 - 1.0;
    let beats: Vec<f64> = beats_s
        .iter()
        .map(|b| b * motion.fps())
        .filter(|f| (0.0..=last).contains(f))
        .collect();
    if beats.is_empty() {
        return None;
    }
    let score: f64 = beats
        .iter()
        .map(|b| {
            let d = minima
                .iter()
                .map(|m| (m - b).abs())
                .fold(f64::INFINITY, f64::min);
            if d.is_finite() {
                (-d * d / (2.0 * sigma_frames * sigma_frames)).exp()
            } else {
                0.0
            }
        })
        .sum();
    Some(score / beats.len() as f64)
}

/// The metrics of one synthesis, as the example and the CLI report them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MotionReport {
    /// Frames.
    pub frames: usize,
    /// Share of frames with the bow outside [0, 1].
    pub bow_range_violations: f64,
    /// Largest bone-length coefficient of variation (3-D).
    pub max_bone_length_cv: f32,
    /// Mean 2-D joint acceleration, pixels / frame².
    pub jitter_px: f32,
    /// Beat alignment (σ = 3 frames), when the performance has beats.
    pub beat_alignment: Option<f64>,
    /// Frames where a wrist missed its target.
    pub unreached_frames: usize,
    /// Share of sounding frames with the bow hair within 5 mm of the played string.
    pub bow_string_contact: Option<f64>,
    /// Share of stopped-note frames with the playing fingertip within 5 mm of its string.
    pub fingertip_string_contact: Option<f64>,
    /// Mean 2-D acceleration of the 42 hand points, pixels / frame².
    pub hand_jitter_px: Option<f32>,
    /// Largest bone-length CV of the whole performer (body, hands, instrument; 3-D).
    pub performer_bone_length_cv: Option<f32>,
}

impl MotionReport {
    /// Measures `synthesis` of `perf`.
    pub fn measure(synthesis: &Synthesis, perf: &Performance) -> MotionReport {
        let m = &synthesis.motion;
        MotionReport {
            frames: m.len(),
            bow_range_violations: bow_range_violations(synthesis.bow.positions()),
            max_bone_length_cv: bone_length_variation(m),
            jitter_px: jitter(m),
            beat_alignment: beat_alignment(m, perf.beats_s(), 3.0),
            unreached_frames: synthesis.unreached_frames,
            bow_string_contact: crate::left_hand::resolve_fingerings(perf.notes())
                .ok()
                .and_then(|fingerings| {
                    let played =
                        contact::played_strings(perf.notes(), &fingerings, m.fps(), m.len());
                    contact::bow_string_contact(m, &played, contact::CONTACT_TOLERANCE_M)
                }),
            fingertip_string_contact: {
                let pressed: Vec<Option<(u8, u8)>> = synthesis
                    .fingers
                    .iter()
                    .map(|f| f.down.map(|d| (d.finger, d.string)))
                    .collect();
                contact::fingertip_string_contact(m, &pressed, contact::CONTACT_TOLERANCE_M)
            },
            hand_jitter_px: contact::hand_jitter_px(m),
            performer_bone_length_cv: m.performer().map(|p| p.max_bone_length_cv()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motion_with_speed_minima_at(minima: &[usize], frames: usize) -> Motion {
        // One coordinate moves with speed |t - nearest minimum| + 1: minima exactly there.
        let mut a = Array3::<f32>::zeros((frames, 10, 2));
        let mut x = 0.0f32;
        for f in 0..frames {
            a[[f, 0, 0]] = x;
            let d = minima
                .iter()
                .map(|&m| (f as i64 - m as i64).unsigned_abs())
                .min()
                .unwrap_or(0);
            x += d as f32 + 1.0;
        }
        Motion::new(30.0, a).unwrap()
    }

    #[test]
    fn beat_alignment_rewards_minima_on_beats() {
        let m = motion_with_speed_minima_at(&[15, 45, 75], 90);
        let on = beat_alignment(&m, &[0.5, 1.5, 2.5], 3.0).unwrap();
        assert!(on > 0.99, "{on}");
        let off = beat_alignment(&m, &[1.0, 2.0], 3.0).unwrap();
        assert!(off < 0.01, "{off}");
        assert_eq!(beat_alignment(&m, &[], 3.0), None);
        assert_eq!(beat_alignment(&m, &[99.0], 3.0), None);
    }

    #[test]
    fn summed_speed_of_a_still_track_is_zero() {
        let s = summed_joint_speed(&Array3::zeros((5, 10, 3)));
        assert!(s.iter().all(|&v| v == 0.0));
        assert!(summed_joint_speed(&Array3::zeros((0, 10, 3))).is_empty());
    }
}
