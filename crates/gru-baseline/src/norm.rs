//! Normalisation of the network's inputs (mel bands) and targets (joint positions).
//!
//! * **Mel**: each band is standardised with the mean and standard deviation of that band
//!   over all training frames ([`MelStats`]), stored with the weights.
//! * **Joints**: each video is normalised on its own ([`VideoNorm`]): subtract the mean
//!   position of the video's **trunk** (neck, both shoulders, both hips, over all frames: one
//!   x and one y) and divide by the video's mean **torso length** (neck to the midpoint of the
//!   hips, in pixels). The torso is the most rigid, least foreshortened span in front views of
//!   a standing violinist, so neither centre nor scale moves with the bowing arm. (SPEC §3
//!   step 4 centres a video on the mean of *all* joints; for a training target that mean is
//!   wrong: it depends on what the bowing arm did in that particular video, so every target
//!   coordinate — hips included — carries a per-video offset no model can hear. Measured on
//!   corpus-mix: crate README.)
//! * **Coordinates**: the network predicts each of the 20 normalised coordinates standardised
//!   with its mean and standard deviation over the training frames ([`TargetSpace`]), so the
//!   left hand (a few pixels of motion, fully determined by the notes) weighs as much in the
//!   loss as the bowing arm (a hundred pixels, mostly its unknowable direction).
//! * **Output**: predictions are turned back into pixels with the training targets' mean
//!   centre and torso length ([`TargetSpace`]), i.e. the image space of the training videos
//!   (the corpus renders them with Method 2's camera, 1280×720), so Method 1's output
//!   overlays Method 2's.

use ndarray::{Array2, ArrayView2, Axis};
use serde::{Deserialize, Serialize};
use skeleton::{Joint, Motion, JOINT_COUNT};

use crate::error::{GruError, Result};

/// Smallest standard deviation used for a band (dB), so silent bands do not explode.
pub const MIN_BAND_STD_DB: f32 = 1e-3;

/// Smallest standard deviation used for a target coordinate (torso lengths, ≈ 2.7 px on the
/// corpus camera), so a joint that barely moves does not dominate the loss.
pub const MIN_COORD_STD: f32 = 0.01;

/// The joints whose mean position centres a video: the trunk.
pub const TRUNK_JOINTS: [Joint; 5] = [
    Joint::Neck,
    Joint::RShoulder,
    Joint::LShoulder,
    Joint::RHip,
    Joint::LHip,
];

/// Per-band mean and standard deviation of the training mel frames (dB).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MelStats {
    /// Mean of each band.
    pub mean: Vec<f32>,
    /// Standard deviation of each band (at least [`MIN_BAND_STD_DB`]).
    pub std: Vec<f32>,
}

impl MelStats {
    /// Identity statistics (mean 0, std 1) for `bands` bands.
    pub fn identity(bands: usize) -> Self {
        Self {
            mean: vec![0.0; bands],
            std: vec![1.0; bands],
        }
    }

    /// Statistics over all frames of all `sequences` (each `(frames, bands)`), in f64.
    ///
    /// ```
    /// let a = ndarray::array![[0.0f32, 10.0], [2.0, 10.0]];
    /// let s = gru_baseline::MelStats::of([a.view()])?;
    /// assert_eq!(s.mean, vec![1.0, 10.0]);
    /// assert_eq!(s.std[0], 1.0);
    /// # Ok::<(), gru_baseline::GruError>(())
    /// ```
    pub fn of<'a>(sequences: impl IntoIterator<Item = ArrayView2<'a, f32>>) -> Result<Self> {
        let mut sum: Vec<f64> = Vec::new();
        let mut sq: Vec<f64> = Vec::new();
        let mut n = 0usize;
        for seq in sequences {
            if sum.is_empty() {
                sum = vec![0.0; seq.ncols()];
                sq = vec![0.0; seq.ncols()];
            }
            if seq.ncols() != sum.len() {
                return Err(GruError::Shape {
                    what: "mel statistics".into(),
                    expected: format!("(frames, {})", sum.len()),
                    got: format!("{:?}", seq.dim()),
                });
            }
            for row in seq.rows() {
                for (k, &v) in row.iter().enumerate() {
                    sum[k] += f64::from(v);
                    sq[k] += f64::from(v) * f64::from(v);
                }
            }
            n += seq.nrows();
        }
        if n == 0 {
            return Err(GruError::Empty("mel statistics".into()));
        }
        let nf = n as f64;
        let mean: Vec<f32> = sum.iter().map(|s| (s / nf) as f32).collect();
        let std = sum
            .iter()
            .zip(&sq)
            .map(|(s, q)| {
                let m = s / nf;
                ((q / nf - m * m).max(0.0).sqrt() as f32).max(MIN_BAND_STD_DB)
            })
            .collect();
        Ok(Self { mean, std })
    }

    /// Number of bands.
    pub fn bands(&self) -> usize {
        self.mean.len()
    }

    /// `(x − mean) / std` per band, into a new array.
    pub fn normalize(&self, mel: ArrayView2<f32>) -> Array2<f32> {
        let mut out = mel.to_owned();
        for mut row in out.rows_mut() {
            for ((v, m), s) in row.iter_mut().zip(&self.mean).zip(&self.std) {
                *v = (*v - m) / s;
            }
        }
        out
    }
}

/// One video's joint normalisation: its trunk's mean position and mean torso length, pixels.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct VideoNorm {
    /// Mean x and y of the [`TRUNK_JOINTS`] over all frames.
    pub center_px: [f32; 2],
    /// Mean distance from the neck to the midpoint of the hips.
    pub torso_px: f32,
}

impl VideoNorm {
    /// Measures `motion`; fails on an empty motion or one without a torso.
    pub fn of(motion: &Motion) -> Result<Self> {
        if motion.is_empty() {
            return Err(GruError::Empty("motion".into()));
        }
        let f = motion.frames();
        let mut torso = 0.0f64;
        let mut center = [0.0f64; 2];
        for t in 0..motion.len() {
            let p = |j: Joint, d: usize| f64::from(f[[t, j.index(), d]]);
            for (d, c) in center.iter_mut().enumerate() {
                *c += TRUNK_JOINTS.iter().map(|&j| p(j, d)).sum::<f64>();
            }
            let hx = 0.5 * (p(Joint::RHip, 0) + p(Joint::LHip, 0));
            let hy = 0.5 * (p(Joint::RHip, 1) + p(Joint::LHip, 1));
            torso += (p(Joint::Neck, 0) - hx).hypot(p(Joint::Neck, 1) - hy);
        }
        let torso_px = (torso / motion.len() as f64) as f32;
        let n = (motion.len() * TRUNK_JOINTS.len()) as f64;
        let (cx, cy) = ((center[0] / n) as f32, (center[1] / n) as f32);
        if !(torso_px.is_finite() && torso_px > 1e-3 && cx.is_finite() && cy.is_finite()) {
            return Err(GruError::Config(format!(
                "the motion has no measurable torso (mean neck-to-hips length {torso_px} px); joints must be in pixels"
            )));
        }
        Ok(Self {
            center_px: [cx, cy],
            torso_px,
        })
    }

    /// The motion's joints as `(frames, 20)` (x, y per joint), centred and scaled.
    pub fn normalize(&self, motion: &Motion) -> Array2<f32> {
        let f = motion.frames();
        let mut out = Array2::zeros((motion.len(), 2 * JOINT_COUNT));
        for (t, mut row) in out.axis_iter_mut(Axis(0)).enumerate() {
            for j in 0..JOINT_COUNT {
                for d in 0..2 {
                    row[2 * j + d] = (f[[t, j, d]] - self.center_px[d]) / self.torso_px;
                }
            }
        }
        out
    }
}

/// Where de-normalised outputs go — the mean centre and torso length of the training
/// targets, and their image size — and how the network's outputs are standardised.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TargetSpace {
    /// Mean of the training videos' centres, pixels.
    pub center_px: [f32; 2],
    /// Mean of the training videos' torso lengths, pixels.
    pub torso_px: f32,
    /// Image size of the training videos, when they all share one.
    pub image_size: Option<(u32, u32)>,
    /// Mean of each normalised coordinate over the training frames (20 values; empty in
    /// weights of format 1: no standardisation).
    #[serde(default)]
    pub coord_mean: Vec<f32>,
    /// Standard deviation of each normalised coordinate (at least [`MIN_COORD_STD`]; empty:
    /// none). The network predicts `(y − coord_mean) / coord_std`.
    #[serde(default)]
    pub coord_std: Vec<f32>,
}

impl Default for TargetSpace {
    /// The corpus camera: 1280×720, centre of the frame, a 230 px torso; no standardisation.
    fn default() -> Self {
        Self {
            center_px: [640.0, 360.0],
            torso_px: 230.0,
            image_size: Some((1280, 720)),
            coord_mean: Vec::new(),
            coord_std: Vec::new(),
        }
    }
}

impl TargetSpace {
    /// The mean of `videos` (and their shared image size), and the statistics of every
    /// coordinate over all frames of `joints` (each `(frames, 20)`, normalised per video).
    ///
    /// ```
    /// use gru_baseline::{TargetSpace, VideoNorm};
    /// let video = VideoNorm { center_px: [600.0, 300.0], torso_px: 250.0 };
    /// let joints = ndarray::Array2::from_shape_fn((4, 20), |(t, k)| (t * k) as f32 * 0.01);
    /// let space = TargetSpace::of(&[(video, None)], [joints.view()])?;
    /// assert_eq!(space.coord_mean[1], 0.015);
    /// assert_eq!(space.coord_std[0], gru_baseline::norm::MIN_COORD_STD);
    /// # Ok::<(), gru_baseline::GruError>(())
    /// ```
    pub fn of<'a>(
        videos: &[(VideoNorm, Option<(u32, u32)>)],
        joints: impl IntoIterator<Item = ArrayView2<'a, f32>>,
    ) -> Result<Self> {
        if videos.is_empty() {
            return Err(GruError::Empty("training videos".into()));
        }
        let n = videos.len() as f32;
        let cx = videos.iter().map(|(v, _)| v.center_px[0]).sum::<f32>() / n;
        let cy = videos.iter().map(|(v, _)| v.center_px[1]).sum::<f32>() / n;
        let torso = videos.iter().map(|(v, _)| v.torso_px).sum::<f32>() / n;
        let first = videos[0].1;
        let image_size = if videos.iter().all(|(_, s)| *s == first) {
            first
        } else {
            None
        };
        let stats = MelStats::of(joints)?;
        if stats.bands() != 2 * JOINT_COUNT {
            return Err(GruError::Shape {
                what: "training joints".into(),
                expected: format!("(frames, {})", 2 * JOINT_COUNT),
                got: format!("{} columns", stats.bands()),
            });
        }
        Ok(Self {
            center_px: [cx, cy],
            torso_px: torso,
            image_size,
            coord_std: stats.std.iter().map(|s| s.max(MIN_COORD_STD)).collect(),
            coord_mean: stats.mean,
        })
    }

    /// Checks sizes and values (finite, positive scales; 0 or 20 coordinate statistics).
    pub fn validate(&self) -> Result<()> {
        let k = self.coord_mean.len();
        if self.coord_std.len() != k || (k != 0 && k != 2 * JOINT_COUNT) {
            return Err(GruError::Config(format!(
                "target statistics have {} means and {} deviations; expected 0 or {} of each",
                k,
                self.coord_std.len(),
                2 * JOINT_COUNT
            )));
        }
        let finite = self
            .center_px
            .iter()
            .chain(&self.coord_mean)
            .all(|v| v.is_finite());
        let positive = std::iter::once(&self.torso_px)
            .chain(&self.coord_std)
            .all(|v| v.is_finite() && *v > 0.0);
        if !(finite && positive) {
            return Err(GruError::Config(
                "target normalisation values must be finite with positive scales".into(),
            ));
        }
        Ok(())
    }

    /// Per-video normalised joints `(frames, 20)` → the network's standardised units.
    pub fn standardize(&self, joints: ArrayView2<f32>) -> Array2<f32> {
        let mut out = joints.to_owned();
        if self.coord_mean.is_empty() {
            return out;
        }
        for mut row in out.rows_mut() {
            for ((v, m), s) in row.iter_mut().zip(&self.coord_mean).zip(&self.coord_std) {
                *v = (*v - m) / s;
            }
        }
        out
    }

    /// The inverse of [`TargetSpace::standardize`], in place.
    pub fn destandardize(&self, mut outputs: Array2<f32>) -> Array2<f32> {
        if self.coord_mean.is_empty() {
            return outputs;
        }
        for mut row in outputs.rows_mut() {
            for ((v, m), s) in row.iter_mut().zip(&self.coord_mean).zip(&self.coord_std) {
                *v = *v * s + m;
            }
        }
        outputs
    }

    /// Turns normalised `(frames, 20)` predictions into a 30 fps [`Motion`] in pixels.
    pub fn to_motion(&self, normalized: ArrayView2<f32>, fps: f64) -> Result<Motion> {
        if normalized.ncols() != 2 * JOINT_COUNT {
            return Err(GruError::Shape {
                what: "predicted joints".into(),
                expected: format!("(frames, {})", 2 * JOINT_COUNT),
                got: format!("{:?}", normalized.dim()),
            });
        }
        let t = normalized.nrows();
        let mut frames = ndarray::Array3::<f32>::zeros((t, JOINT_COUNT, 2));
        for (f, row) in normalized.rows().into_iter().enumerate() {
            for j in 0..JOINT_COUNT {
                for d in 0..2 {
                    frames[[f, j, d]] = row[2 * j + d] * self.torso_px + self.center_px[d];
                }
            }
        }
        let motion = Motion::new(fps, frames)?;
        Ok(match self.image_size {
            Some((w, h)) => motion.with_image_size(w, h),
            None => motion,
        })
    }
}
