//! Small 3-D vector and rotation-matrix types (f64) for 3-D motion (motion-synth's rig, BVH).
//!
//! World frame: metres, x to the player's left, y up, z forward (the way the
//! player faces). Rotation matrices act on column vectors.

use std::ops::{Add, Mul, Neg, Sub};

/// A 3-D vector or point in metres.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vec3 {
    /// x: towards the player's left.
    pub x: f64,
    /// y: up.
    pub y: f64,
    /// z: forward, the way the player faces.
    pub z: f64,
}

impl Vec3 {
    /// The zero vector.
    pub const ZERO: Vec3 = Vec3::new(0.0, 0.0, 0.0);
    /// Unit x (the player's left).
    pub const X: Vec3 = Vec3::new(1.0, 0.0, 0.0);
    /// Unit y (up).
    pub const Y: Vec3 = Vec3::new(0.0, 1.0, 0.0);
    /// Unit z (forward).
    pub const Z: Vec3 = Vec3::new(0.0, 0.0, 1.0);

    /// A vector from its coordinates.
    pub const fn new(x: f64, y: f64, z: f64) -> Vec3 {
        Vec3 { x, y, z }
    }

    /// Dot product.
    pub fn dot(self, o: Vec3) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product.
    pub fn cross(self, o: Vec3) -> Vec3 {
        Vec3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// Euclidean length.
    pub fn length(self) -> f64 {
        self.dot(self).sqrt()
    }

    /// The unit vector in this direction, or `fallback` when the length is (nearly) zero.
    pub fn normalized_or(self, fallback: Vec3) -> Vec3 {
        let len = self.length();
        if len > 1e-12 {
            self * (1.0 / len)
        } else {
            fallback
        }
    }

    /// Linear interpolation `self + (o - self) * t`.
    pub fn lerp(self, o: Vec3, t: f64) -> Vec3 {
        self + (o - self) * t
    }

    /// The coordinates as an array.
    pub fn to_array(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
}

impl Add for Vec3 {
    type Output = Vec3;
    fn add(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for Vec3 {
    type Output = Vec3;
    fn sub(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Neg for Vec3 {
    type Output = Vec3;
    fn neg(self) -> Vec3 {
        Vec3::new(-self.x, -self.y, -self.z)
    }
}

impl Mul<f64> for Vec3 {
    type Output = Vec3;
    fn mul(self, s: f64) -> Vec3 {
        Vec3::new(self.x * s, self.y * s, self.z * s)
    }
}

/// A 3×3 matrix (rows), used for rotations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mat3 {
    /// The rows.
    pub rows: [[f64; 3]; 3],
}

impl Mat3 {
    /// The identity.
    pub const IDENTITY: Mat3 = Mat3 {
        rows: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };

    /// The matrix whose columns are `c0`, `c1`, `c2`.
    pub fn from_columns(c0: Vec3, c1: Vec3, c2: Vec3) -> Mat3 {
        Mat3 {
            rows: [[c0.x, c1.x, c2.x], [c0.y, c1.y, c2.y], [c0.z, c1.z, c2.z]],
        }
    }

    /// Column `i` (0..3).
    pub fn column(&self, i: usize) -> Vec3 {
        let r = &self.rows;
        Vec3::new(r[0][i], r[1][i], r[2][i])
    }

    /// Rotation by `angle_rad` about the x axis (positive turns +y towards +z).
    pub fn rot_x(angle_rad: f64) -> Mat3 {
        let (s, c) = angle_rad.sin_cos();
        Mat3 {
            rows: [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
        }
    }

    /// Rotation by `angle_rad` about the y axis (positive turns +z towards +x).
    pub fn rot_y(angle_rad: f64) -> Mat3 {
        let (s, c) = angle_rad.sin_cos();
        Mat3 {
            rows: [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
        }
    }

    /// Rotation by `angle_rad` about the z axis (positive turns +x towards +y).
    pub fn rot_z(angle_rad: f64) -> Mat3 {
        let (s, c) = angle_rad.sin_cos();
        Mat3 {
            rows: [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
        }
    }

    /// Rotation by `angle_rad` about the unit vector `axis` (right-hand rule).
    pub fn axis_angle(axis: Vec3, angle_rad: f64) -> Mat3 {
        let (s, c) = angle_rad.sin_cos();
        let t = 1.0 - c;
        let Vec3 { x, y, z } = axis;
        Mat3 {
            rows: [
                [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
                [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
                [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
            ],
        }
    }

    /// The transpose (the inverse of a rotation).
    pub fn transpose(&self) -> Mat3 {
        let r = &self.rows;
        Mat3 {
            rows: [
                [r[0][0], r[1][0], r[2][0]],
                [r[0][1], r[1][1], r[2][1]],
                [r[0][2], r[1][2], r[2][2]],
            ],
        }
    }
}

impl Mul<Vec3> for Mat3 {
    type Output = Vec3;
    fn mul(self, v: Vec3) -> Vec3 {
        let r = &self.rows;
        Vec3::new(
            r[0][0] * v.x + r[0][1] * v.y + r[0][2] * v.z,
            r[1][0] * v.x + r[1][1] * v.y + r[1][2] * v.z,
            r[2][0] * v.x + r[2][1] * v.y + r[2][2] * v.z,
        )
    }
}

impl Mul for Mat3 {
    type Output = Mat3;
    fn mul(self, o: Mat3) -> Mat3 {
        let mut rows = [[0.0; 3]; 3];
        for (i, row) in rows.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = (0..3).map(|k| self.rows[i][k] * o.rows[k][j]).sum();
            }
        }
        Mat3 { rows }
    }
}

/// A rigid transform: `p ↦ rotation · p + translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// The rotation.
    pub rotation: Mat3,
    /// The translation (metres).
    pub translation: Vec3,
}

impl Transform {
    /// Applies the transform to a point.
    pub fn apply(&self, p: Vec3) -> Vec3 {
        self.rotation * p + self.translation
    }
}

/// Smoothstep `3u² − 2u³` of `u` clamped to [0, 1]: 0 → 0, 1 → 1, zero slope at both ends.
pub fn smoothstep(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * (3.0 - 2.0 * u)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn rotations_follow_the_right_hand_rule() {
        let q = std::f64::consts::FRAC_PI_2;
        assert!(close(Mat3::rot_x(q) * Vec3::Y, Vec3::Z));
        assert!(close(Mat3::rot_y(q) * Vec3::Z, Vec3::X));
        assert!(close(Mat3::rot_z(q) * Vec3::X, Vec3::Y));
        let axis = Vec3::new(1.0, 2.0, -0.5).normalized_or(Vec3::X);
        let m = Mat3::axis_angle(axis, 0.7);
        assert!(close(m * axis, axis));
        let back = m.transpose() * (m * Vec3::new(0.3, -0.2, 0.9));
        assert!(close(back, Vec3::new(0.3, -0.2, 0.9)));
        assert!(close(
            Mat3::axis_angle(Vec3::X, 0.4) * Vec3::Y,
            Mat3::rot_x(0.4) * Vec3::Y
        ));
    }

    #[test]
    fn smoothstep_is_flat_at_the_ends() {
        assert_eq!(smoothstep(-1.0), 0.0);
        assert_eq!(smoothstep(0.5), 0.5);
        assert_eq!(smoothstep(2.0), 1.0);
        assert!(smoothstep(1e-3) < 1e-5);
    }
}
