//! Plausibility metrics of a motion: jitter and bone-length constancy.

use ndarray::{Array2, Array3, Axis};

use crate::joint::{BONES, JOINT_COUNT};
use crate::motion::Motion;

/// Mean |second difference| (acceleration, units per frame²) of each joint of a track
/// `(T, J, D)`; zeros when there are fewer than 3 frames.
pub fn jitter_per_joint(track: &Array3<f32>) -> Vec<f32> {
    let (t, j, _) = track.dim();
    (0..j)
        .map(|k| {
            if t < 3 {
                return 0.0;
            }
            let p = track.index_axis(Axis(1), k);
            let sum: f64 = (1..t - 1)
                .map(|i| {
                    let a = p.row(i - 1);
                    let b = p.row(i);
                    let c = p.row(i + 1);
                    let sq: f32 = (0..a.len())
                        .map(|d| {
                            let acc = a[d] - 2.0 * b[d] + c[d];
                            acc * acc
                        })
                        .sum();
                    f64::from(sq.sqrt())
                })
                .sum();
            (sum / (t - 2) as f64) as f32
        })
        .collect()
}

/// Lengths of [`BONES`] in every frame of a joint track `(T, 10, D)`: `(T, 10)`.
pub fn bone_lengths(track: &Array3<f32>) -> Array2<f32> {
    let t = track.len_of(Axis(0));
    let mut out = Array2::zeros((t, BONES.len()));
    for (f, mut row) in out.rows_mut().into_iter().enumerate() {
        for (b, (j0, j1)) in BONES.iter().enumerate() {
            let p = track.slice(ndarray::s![f, j0.index(), ..]);
            let q = track.slice(ndarray::s![f, j1.index(), ..]);
            row[b] = p
                .iter()
                .zip(q.iter())
                .map(|(a, c)| (a - c) * (a - c))
                .sum::<f32>()
                .sqrt();
        }
    }
    out
}

/// Coefficient of variation (std / mean) of each bone's length over time; 0 for a bone of
/// zero mean length.
pub fn bone_length_cv(track: &Array3<f32>) -> Vec<f32> {
    let lengths = bone_lengths(track);
    lengths
        .columns()
        .into_iter()
        .map(|c| {
            let n = c.len().max(1) as f64;
            let mean = c.iter().map(|&v| f64::from(v)).sum::<f64>() / n;
            if mean <= 0.0 {
                return 0.0;
            }
            let var = c
                .iter()
                .map(|&v| (f64::from(v) - mean).powi(2))
                .sum::<f64>()
                / n;
            (var.sqrt() / mean) as f32
        })
        .collect()
}

impl Motion {
    /// Mean acceleration magnitude of each 2-D joint (pixels / frame²).
    pub fn jitter_per_joint(&self) -> [f32; JOINT_COUNT] {
        let v = jitter_per_joint(self.frames());
        std::array::from_fn(|i| v.get(i).copied().unwrap_or(0.0))
    }

    /// Mean of [`Motion::jitter_per_joint`].
    pub fn jitter(&self) -> f32 {
        self.jitter_per_joint().iter().sum::<f32>() / JOINT_COUNT as f32
    }

    /// Largest bone-length coefficient of variation: of the 3-D track when there is one
    /// (true lengths), else of the 2-D track (projected lengths, which foreshorten).
    pub fn max_bone_length_cv(&self) -> f32 {
        let track = self.frames_3d().unwrap_or(self.frames());
        bone_length_cv(track).into_iter().fold(0.0, f32::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::Array3;

    #[test]
    fn still_pose_has_no_jitter_and_constant_bones() {
        let mut a = Array3::<f32>::zeros((20, JOINT_COUNT, 2));
        for f in 0..20 {
            for j in 0..JOINT_COUNT {
                a[[f, j, 0]] = j as f32 * 10.0;
                a[[f, j, 1]] = (j * j) as f32;
            }
        }
        let m = Motion::new(30.0, a).unwrap();
        assert_eq!(m.jitter(), 0.0);
        assert!(m.max_bone_length_cv() < 1e-6);
    }

    #[test]
    fn jitter_measures_acceleration() {
        let mut a = Array3::<f32>::zeros((5, JOINT_COUNT, 2));
        a[[2, 0, 0]] = 1.0; // a one-frame spike on the nose: |acc| = 1, 2, 1
        let j = jitter_per_joint(&a);
        assert!((j[0] - 4.0 / 3.0).abs() < 1e-6);
        assert_eq!(j[1], 0.0);
    }

    #[test]
    fn centring_zeroes_the_mean() {
        let a = Array3::<f32>::from_shape_fn((4, JOINT_COUNT, 2), |(t, j, c)| {
            (t * 7 + j * 3 + c * 100) as f32
        });
        let mut m = Motion::new(30.0, a).unwrap();
        m.center();
        let (x, y) = m.mean_xy();
        assert!(x.abs() < 1e-4 && y.abs() < 1e-4);
    }

    #[test]
    fn shapes_and_fps_are_checked() {
        assert!(Motion::new(0.0, Array3::zeros((1, JOINT_COUNT, 2))).is_err());
        assert!(Motion::new(30.0, Array3::zeros((1, 9, 2))).is_err());
        let m = Motion::new(30.0, Array3::zeros((3, JOINT_COUNT, 2))).unwrap();
        assert!(m
            .clone()
            .with_3d(Array3::zeros((4, JOINT_COUNT, 3)))
            .is_err());
        assert!(m.with_3d(Array3::zeros((3, JOINT_COUNT, 3))).is_ok());
    }
}
