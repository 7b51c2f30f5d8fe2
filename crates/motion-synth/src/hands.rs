//! The two 21-point hands: a rigid palm in a hand frame, and fingers whose tips are placed
//! by inverse kinematics (every phalanx keeps its length exactly).
//!
//! A finger is its base knuckle and three phalanges. The last joint (DIP) keeps a fixed
//! bend, so knuckle → middle joint → tip is a two-link chain ([`two_link`]); the DIP is
//! then the elbow of a second two-link chain between the middle joint and the tip.

use skeleton::{Finger, HAND_POINT_COUNT};

use crate::geometry::{Mat3, Vec3};
use crate::ik::two_link;

/// Phalanx lengths (metres) of thumb, index, middle, ring and little finger: base knuckle →
/// middle joint → last joint → tip (for the thumb: CMC → MCP → IP → tip).
pub const PHALANGES_M: [[f64; 3]; 5] = [
    [0.040, 0.032, 0.027],
    [0.042, 0.025, 0.020],
    [0.046, 0.028, 0.021],
    [0.043, 0.027, 0.020],
    [0.034, 0.020, 0.018],
];

/// Fixed bend of the last finger joint, radians.
const DIP_BEND_RAD: f64 = 0.45;

/// Places one finger: `base` is its base knuckle, `target` where the tip should go, `pole`
/// the direction the middle joint bulges towards. Returns base, middle joint, last joint
/// and tip (the tip is the target, or the nearest reachable point towards it).
pub fn place_finger(base: Vec3, target: Vec3, lengths: [f64; 3], pole: Vec3) -> [Vec3; 4] {
    let [lp, lm, ld] = lengths;
    let virtual_len = (lm * lm + ld * ld + 2.0 * lm * ld * DIP_BEND_RAD.cos()).sqrt();
    let first = two_link(base, target, lp, virtual_len, pole);
    let second = two_link(first.elbow, first.wrist, lm, ld, pole);
    [base, first.elbow, second.elbow, first.wrist]
}

/// The hand's 21 points from its wrist, the five base knuckles (thumb first) and the five
/// tip targets, with one pole for all fingers.
pub fn hand_points(
    wrist: Vec3,
    bases: &[Vec3; 5],
    targets: &[Vec3; 5],
    pole: Vec3,
) -> [Vec3; HAND_POINT_COUNT] {
    let mut out = [wrist; HAND_POINT_COUNT];
    for (i, finger) in Finger::ALL.into_iter().enumerate() {
        let chain = place_finger(bases[i], targets[i], PHALANGES_M[i], pole);
        for (k, p) in chain.into_iter().enumerate() {
            out[finger.point(k + 1)] = p;
        }
    }
    out
}

/// Base knuckles of the left hand relative to its wrist, violin-local axes (the palm under
/// the neck, knuckles on the E side above the fingerboard, the thumb on the G side).
pub const LEFT_BASES_LOCAL: [Vec3; 5] = [
    Vec3::new(0.018, 0.030, -0.012),
    Vec3::new(-0.040, 0.085, -0.010),
    Vec3::new(-0.042, 0.082, -0.027),
    Vec3::new(-0.041, 0.078, -0.043),
    Vec3::new(-0.037, 0.072, -0.057),
];

/// The right hand's frame at `wrist` holding the bow at `frog` along `bow_dir`: columns are
/// towards the frog (a), along the bow (b) and a × b.
pub fn right_hand_frame(wrist: Vec3, frog: Vec3, bow_dir: Vec3) -> Mat3 {
    let a = (frog - wrist).normalized_or(Vec3::Z);
    let b = (bow_dir - a * bow_dir.dot(a)).normalized_or(Vec3::X);
    Mat3::from_columns(a, b, a.cross(b))
}

/// Base knuckles of the right hand in its frame ([`right_hand_frame`]).
pub const RIGHT_BASES_LOCAL: [Vec3; 5] = [
    Vec3::new(0.030, 0.020, -0.020),
    Vec3::new(0.075, 0.024, 0.0),
    Vec3::new(0.078, 0.006, 0.0),
    Vec3::new(0.074, -0.011, 0.0),
    Vec3::new(0.066, -0.026, 0.0),
];

/// Where the right fingertips hold the bow, in (along the bow from the frog, towards the
/// stick's top, away from the wrist) metres from the stick at the frog; the thumb is under
/// the stick, the little finger on top of it.
pub const RIGHT_GRIP: [[f64; 3]; 5] = [
    [0.022, -0.012, -0.004],
    [0.062, -0.006, 0.012],
    [0.045, -0.010, 0.013],
    [0.030, -0.010, 0.012],
    [0.014, 0.010, 0.002],
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phalanges_keep_their_lengths_reached_or_not() {
        let base = Vec3::new(0.0, 0.0, 0.0);
        for target in [Vec3::new(0.05, -0.03, 0.0), Vec3::new(0.5, 0.0, 0.0), base] {
            let c = place_finger(base, target, PHALANGES_M[1], Vec3::Y);
            for (k, len) in PHALANGES_M[1].iter().enumerate() {
                assert!(((c[k + 1] - c[k]).length() - len).abs() < 1e-9);
            }
        }
        let reach = place_finger(base, Vec3::new(0.05, -0.03, 0.0), PHALANGES_M[1], Vec3::Y);
        assert!((reach[3] - Vec3::new(0.05, -0.03, 0.0)).length() < 1e-12);
        assert!(reach[1].y > 0.0, "the middle joint bulges towards the pole");
    }
}
