//! Euler angles of a rotation in BVH's `Zrotation Xrotation Yrotation` order.

use crate::geometry::Mat3;

/// `(z, x, y)` angles in degrees with `m = Rz(z) · Rx(x) · Ry(y)`.
pub(super) fn euler_zxy(m: &Mat3) -> [f64; 3] {
    let r = &m.rows;
    let x = r[2][1].clamp(-1.0, 1.0).asin();
    let (z, y) = if x.cos() > 1e-9 {
        ((-r[0][1]).atan2(r[1][1]), (-r[2][0]).atan2(r[2][2]))
    } else {
        (r[1][0].atan2(r[0][0]), 0.0)
    };
    [z.to_degrees(), x.to_degrees(), y.to_degrees()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec3;

    #[test]
    fn euler_zxy_round_trips() {
        for (z, x, y) in [
            (10.0, 20.0, 30.0),
            (-170.0, 80.0, 5.0),
            (45.0, -60.0, -120.0),
            (0.0, 0.0, 0.0),
        ] {
            let m = Mat3::rot_z(f64::to_radians(z))
                * Mat3::rot_x(f64::to_radians(x))
                * Mat3::rot_y(f64::to_radians(y));
            let [a, b, c] = euler_zxy(&m);
            let back = Mat3::rot_z(a.to_radians())
                * Mat3::rot_x(b.to_radians())
                * Mat3::rot_y(c.to_radians());
            for i in 0..3 {
                for j in 0..3 {
                    assert!((back.rows[i][j] - m.rows[i][j]).abs() < 1e-9);
                }
            }
        }
        // Gimbal lock (x = 90°) still gives the same rotation.
        let m = Mat3::rot_z(0.3) * Mat3::rot_x(std::f64::consts::FRAC_PI_2) * Mat3::rot_y(0.2);
        let [a, b, c] = euler_zxy(&m);
        let back =
            Mat3::rot_z(a.to_radians()) * Mat3::rot_x(b.to_radians()) * Mat3::rot_y(c.to_radians());
        assert!((back * Vec3::new(0.1, 0.7, -0.3) - m * Vec3::new(0.1, 0.7, -0.3)).length() < 1e-9);
    }
}
