//! The violin's strings and parts in violin-local coordinates (metres; x across the strings
//! towards G, y the top's normal, z along the strings from the end button to the scroll).

use skeleton::InstrumentPart;

use crate::geometry::Vec3;
use crate::rig::ViolinGeometry;

impl ViolinGeometry {
    /// The point of string `s` (a continuous index, 0 = G … 3 = E; a fraction lies between
    /// two strings) at `from_bridge_m` from the bridge towards the nut. Strings are straight
    /// lines from bridge to nut; the bridge and nut are curved (outer strings lower).
    pub fn string_local(&self, s: f64, from_bridge_m: f64) -> Vec3 {
        let s = s.clamp(0.0, 3.0);
        let u = from_bridge_m / self.string_length;
        let off = s - 1.5;
        let spacing = self.string_spacing + (self.nut_string_spacing - self.string_spacing) * u;
        let at_bridge = self.string_height - 0.004 * off * off;
        let at_nut = self.nut_string_height - 0.0015 * off * off;
        Vec3::new(
            -off * spacing,
            at_bridge + (at_nut - at_bridge) * u,
            self.bridge_from_end + from_bridge_m,
        )
    }

    /// Distance from the bridge at which a string stopped `semitones` above its open pitch
    /// vibrates: `L · 2^(−semitones/12)` (so `L · (1 − 2^(−semitones/12))` from the nut).
    ///
    /// ```
    /// let v = motion_synth::ViolinGeometry::default();
    /// assert!((v.stop_from_bridge(12.0) - v.string_length / 2.0).abs() < 1e-12);
    /// assert_eq!(v.stop_from_bridge(0.0), v.string_length);
    /// ```
    pub fn stop_from_bridge(&self, semitones: f64) -> f64 {
        self.string_length * (-semitones.max(0.0) / 12.0).exp2()
    }

    /// A violin part in violin-local coordinates; `None` for the bow's points.
    pub fn part_local(&self, part: InstrumentPart) -> Option<Vec3> {
        let nut = self.bridge_from_end + self.string_length;
        Some(match part {
            InstrumentPart::ViolinScroll => Vec3::new(0.0, 0.0, self.length),
            InstrumentPart::ViolinNut => Vec3::new(0.0, self.nut_string_height, nut),
            InstrumentPart::ViolinBody => Vec3::new(0.0, 0.0, self.bridge_from_end),
            InstrumentPart::ViolinBridge => {
                Vec3::new(0.0, self.string_height, self.bridge_from_end)
            }
            InstrumentPart::ViolinEndButton => Vec3::ZERO,
            InstrumentPart::StringAtNut(s) => self.string_local(f64::from(s), self.string_length),
            InstrumentPart::StringAtBridge(s) => self.string_local(f64::from(s), 0.0),
            _ => return None,
        })
    }
}

/// Distance from point `p` to the segment `a`–`b`, and the segment parameter of the
/// nearest point (0 at `a`, 1 at `b`).
pub fn point_segment_distance(p: Vec3, a: Vec3, b: Vec3) -> (f64, f64) {
    let ab = b - a;
    let len2 = ab.dot(ab);
    let u = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((a + ab * u - p).length(), u)
}

/// Shortest distance between segments `p0`–`p1` and `q0`–`q1` (closest points of the two
/// lines, clamped to the segments).
pub fn segment_distance(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> f64 {
    let d1 = p1 - p0;
    let d2 = q1 - q0;
    let r = p0 - q0;
    let (a, e, f) = (d1.dot(d1), d2.dot(d2), d2.dot(r));
    let (mut s, mut t);
    if a <= 1e-18 && e <= 1e-18 {
        return r.length();
    }
    if a <= 1e-18 {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(r);
        if e <= 1e-18 {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            s = if denom > 1e-18 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
        }
    }
    ((p0 + d1 * s) - (q0 + d2 * t)).length()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_run_from_bridge_to_nut_and_segments_measure_distance() {
        let v = ViolinGeometry::default();
        let g_bridge = v.part_local(InstrumentPart::StringAtBridge(0)).unwrap();
        let g_nut = v.part_local(InstrumentPart::StringAtNut(0)).unwrap();
        assert!(g_bridge.x > 0.0 && g_nut.z > g_bridge.z);
        assert!(((g_nut - g_bridge).length() - v.string_length).abs() < 0.01);
        let x = Vec3::X;
        let d = segment_distance(
            Vec3::ZERO,
            x,
            Vec3::new(0.5, 1.0, -1.0),
            Vec3::new(0.5, 1.0, 1.0),
        );
        assert!((d - 1.0).abs() < 1e-12);
        let (d, u) = point_segment_distance(Vec3::new(2.0, 1.0, 0.0), Vec3::ZERO, x);
        assert!((d - 2f64.sqrt()).abs() < 1e-12 && u == 1.0);
    }
}
