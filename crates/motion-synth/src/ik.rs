//! Two-link inverse kinematics (shoulder → elbow → wrist) with a pole direction.

use crate::geometry::Vec3;

/// Result of [`two_link`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoLinkSolution {
    /// Elbow position.
    pub elbow: Vec3,
    /// Wrist position: the target, or the nearest reachable point on the line
    /// shoulder → target when the target is out of reach (or too close).
    pub wrist: Vec3,
    /// `true` when the wrist is at the target.
    pub reached: bool,
}

/// Places the elbow of an arm with segments `upper` and `lower` (metres) so that the wrist
/// reaches `target` from `shoulder`, bending towards `pole` (a direction; the elbow lies in
/// the plane of shoulder, target and `shoulder + pole`). The segment lengths are exact by
/// construction, reached or not.
///
/// ```
/// use motion_synth::geometry::Vec3;
/// use motion_synth::ik::two_link;
/// let s = two_link(Vec3::ZERO, Vec3::new(0.0, -0.5, 0.0), 0.3, 0.27, Vec3::Z);
/// assert!(s.reached);
/// assert!(((s.elbow - Vec3::ZERO).length() - 0.3).abs() < 1e-12);
/// assert!(s.elbow.z > 0.0); // bent towards the pole
/// ```
pub fn two_link(
    shoulder: Vec3,
    target: Vec3,
    upper: f64,
    lower: f64,
    pole: Vec3,
) -> TwoLinkSolution {
    let to_target = target - shoulder;
    let dist = to_target.length();
    // Keep the triangle strictly non-degenerate so the elbow stays well defined.
    let min_d = (upper - lower).abs() + 1e-6;
    let max_d = upper + lower - 1e-6;
    let d = dist.clamp(min_d, max_d);
    let reached = (d - dist).abs() < 1e-9;
    let dir = to_target.normalized_or(Vec3::new(0.0, -1.0, 0.0));
    // Pole component perpendicular to the shoulder → wrist line.
    let mut side = pole - dir * pole.dot(dir);
    if side.length() < 1e-9 {
        let alt = if dir.y.abs() < 0.9 { Vec3::Y } else { Vec3::Z };
        side = alt - dir * alt.dot(dir);
    }
    let side = side.normalized_or(Vec3::Z);
    let along = (upper * upper + d * d - lower * lower) / (2.0 * d);
    let height = (upper * upper - along * along).max(0.0).sqrt();
    let elbow = shoulder + dir * along + side * height;
    let wrist = shoulder + dir * d;
    TwoLinkSolution {
        elbow,
        wrist,
        reached,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_are_exact_reachable_or_not() {
        let s = Vec3::new(0.1, 1.4, 0.0);
        for target in [
            Vec3::new(0.4, 1.2, 0.3),
            Vec3::new(2.0, 1.4, 0.0),  // too far
            Vec3::new(0.1, 1.41, 0.0), // too close
            Vec3::new(0.1, 1.4, 0.0),  // on the shoulder
        ] {
            let sol = two_link(s, target, 0.30, 0.27, Vec3::new(0.0, -1.0, 0.0));
            assert!(((sol.elbow - s).length() - 0.30).abs() < 1e-9);
            assert!(((sol.wrist - sol.elbow).length() - 0.27).abs() < 1e-9);
        }
        let far = two_link(s, Vec3::new(2.0, 1.4, 0.0), 0.30, 0.27, Vec3::Y);
        assert!(!far.reached);
        let near = two_link(s, Vec3::new(0.4, 1.2, 0.3), 0.30, 0.27, Vec3::Y);
        assert!(near.reached && (near.wrist - Vec3::new(0.4, 1.2, 0.3)).length() < 1e-12);
    }
}
