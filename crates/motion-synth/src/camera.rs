//! A pinhole camera that turns the rig's world points into image pixels (y down).

use crate::geometry::Vec3;

/// A pinhole camera. The default looks at the player from the front, 10° round towards
/// the player's right (so the violin, which points forward-left, is seen nearly side-on),
/// from a little above eye height 3.2 m away, framing the upper body in a 1280×720 image.
///
/// ```
/// use motion_synth::{Camera, geometry::Vec3};
/// let cam = Camera::default();
/// let [x, y] = cam.project(cam.target);
/// assert!((x - 640.0).abs() < 1e-9 && (y - 360.0).abs() < 1e-9);
/// // The player's left (+x) appears on the image's right; up is up.
/// assert!(cam.project(cam.target + Vec3::X * 0.1)[0] > 640.0);
/// assert!(cam.project(cam.target + Vec3::Y * 0.1)[1] < 360.0);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    /// Image width, pixels.
    pub width_px: u32,
    /// Image height, pixels.
    pub height_px: u32,
    /// Focal length, pixels.
    pub focal_px: f64,
    /// Camera centre, world metres.
    pub eye: Vec3,
    /// The point imaged at the image centre.
    pub target: Vec3,
}

impl Default for Camera {
    fn default() -> Self {
        Camera::orbit(1280, 720, 10.0, 3.2)
    }
}

impl Camera {
    /// A camera at `distance_m` from the upper body, turned `azimuth_deg` from straight in
    /// front towards the player's right (negative: towards the left), with a focal length
    /// that frames about 1.25 m of height at that distance.
    pub fn orbit(width_px: u32, height_px: u32, azimuth_deg: f64, distance_m: f64) -> Camera {
        let target = Vec3::new(0.0, 1.32, 0.15);
        let a = azimuth_deg.to_radians();
        let eye =
            target + Vec3::new(-a.sin(), 0.0, a.cos()) * distance_m + Vec3::new(0.0, 0.35, 0.0);
        let focal_px = f64::from(height_px) * distance_m / 1.25;
        Camera {
            width_px,
            height_px,
            focal_px,
            eye,
            target,
        }
    }

    /// The camera's right, up and forward unit vectors.
    fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let forward = (self.target - self.eye).normalized_or(-Vec3::Z);
        let right = forward.cross(Vec3::Y).normalized_or(Vec3::X);
        let up = right.cross(forward);
        (right, up, forward)
    }

    /// Checks that the camera can image anything.
    pub fn is_valid(&self) -> bool {
        self.width_px > 0
            && self.height_px > 0
            && self.focal_px.is_finite()
            && self.focal_px > 0.0
            && (self.target - self.eye).length() > 1e-6
            && (self.target - self.eye)
                .normalized_or(Vec3::ZERO)
                .cross(Vec3::Y)
                .length()
                > 1e-6
    }

    /// Pixel coordinates `[x, y]` (y down) of a world point. Points at or behind the
    /// camera plane are pushed to a depth of 1 mm rather than producing infinities.
    pub fn project(&self, p: Vec3) -> [f64; 2] {
        let (right, up, forward) = self.basis();
        self.project_with(p, right, up, forward)
    }

    /// A projector with the basis computed once, for per-frame use.
    pub fn projector(&self) -> impl Fn(Vec3) -> [f64; 2] + '_ {
        let (right, up, forward) = self.basis();
        move |p| self.project_with(p, right, up, forward)
    }

    fn project_with(&self, p: Vec3, right: Vec3, up: Vec3, forward: Vec3) -> [f64; 2] {
        let d = p - self.eye;
        let depth = d.dot(forward).max(1e-3);
        let cx = f64::from(self.width_px) / 2.0;
        let cy = f64::from(self.height_px) / 2.0;
        [
            cx + self.focal_px * d.dot(right) / depth,
            cy - self.focal_px * d.dot(up) / depth,
        ]
    }
}
