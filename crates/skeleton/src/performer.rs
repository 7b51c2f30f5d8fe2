//! The whole performer beyond the ten core joints: the BODY_25 body, both 21-point hands
//! and the violin and bow, in image pixels and (optionally) in metres.

use ndarray::{Array3, Axis};

use crate::body25::{BodyPoint, BODY25_BONES, BODY25_COUNT};
use crate::error::{Result, SkeletonError};
use crate::hand::{HAND_BONES, HAND_POINT_COUNT, HAND_POINT_NAMES};
use crate::instrument_parts::{InstrumentPart, INSTRUMENT_BONES, INSTRUMENT_PART_COUNT};
use crate::metrics::jitter_per_joint;

/// One group of points of a [`PerformerTrack`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PerformerPart {
    /// The 25 BODY_25 points ([`BodyPoint::ALL`]).
    Body,
    /// The left (fingering) hand, 21 points ([`HAND_POINT_NAMES`]).
    LeftHand,
    /// The right (bow) hand, 21 points.
    RightHand,
    /// Violin and bow ([`InstrumentPart::ALL`]).
    Instrument,
}

impl PerformerPart {
    /// All parts, in file order.
    pub const ALL: [PerformerPart; 4] = [
        PerformerPart::Body,
        PerformerPart::LeftHand,
        PerformerPart::RightHand,
        PerformerPart::Instrument,
    ];

    /// Number of points of this part.
    pub fn point_count(self) -> usize {
        match self {
            PerformerPart::Body => BODY25_COUNT,
            PerformerPart::LeftHand | PerformerPart::RightHand => HAND_POINT_COUNT,
            PerformerPart::Instrument => INSTRUMENT_PART_COUNT,
        }
    }

    /// The file name of this part's track (`body`, `left_hand`, `right_hand`, `instrument`).
    pub fn name(self) -> &'static str {
        match self {
            PerformerPart::Body => "body",
            PerformerPart::LeftHand => "left_hand",
            PerformerPart::RightHand => "right_hand",
            PerformerPart::Instrument => "instrument",
        }
    }

    /// The names of this part's points, in track order.
    pub fn point_names(self) -> Vec<&'static str> {
        match self {
            PerformerPart::Body => BodyPoint::ALL.iter().map(|p| p.name()).collect(),
            PerformerPart::LeftHand | PerformerPart::RightHand => HAND_POINT_NAMES.to_vec(),
            PerformerPart::Instrument => InstrumentPart::ALL.iter().map(|p| p.name()).collect(),
        }
    }

    /// The rigid bones of this part, as point-index pairs.
    pub fn bones(self) -> Vec<(usize, usize)> {
        match self {
            PerformerPart::Body => BODY25_BONES
                .iter()
                .map(|(a, b)| (a.index(), b.index()))
                .collect(),
            PerformerPart::LeftHand | PerformerPart::RightHand => HAND_BONES.to_vec(),
            PerformerPart::Instrument => INSTRUMENT_BONES
                .iter()
                .map(|(a, b)| (a.index(), b.index()))
                .collect(),
        }
    }
}

/// Body, hands and instrument over time: for each [`PerformerPart`] a `(T, points, 2)` track
/// in image pixels (y down, the same image as the motion's core track) and optionally a
/// `(T, points, 3)` track in metres (x to the player's left, y up, z forward).
///
/// ```
/// use ndarray::Array3;
/// use skeleton::{PerformerPart, PerformerTrack};
/// let t = |p: PerformerPart| Array3::<f32>::zeros((5, p.point_count(), 2));
/// let track = PerformerTrack::new(PerformerPart::ALL.map(t))?;
/// assert_eq!(track.len(), 5);
/// assert!(track.track_3d(PerformerPart::Body).is_none());
/// # Ok::<(), skeleton::SkeletonError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PerformerTrack {
    px: [Array3<f32>; 4],
    metres: Option<[Array3<f32>; 4]>,
}

fn check(parts: &[Array3<f32>; 4], dims: usize, frames: Option<usize>) -> Result<usize> {
    let frames = frames.unwrap_or_else(|| parts[0].len_of(Axis(0)));
    for (part, a) in PerformerPart::ALL.iter().zip(parts) {
        let (t, p, c) = a.dim();
        if t != frames || p != part.point_count() || c != dims {
            return Err(SkeletonError::Shape {
                expected: format!(
                    "performer {}: ({frames}, {}, {dims})",
                    part.name(),
                    part.point_count()
                ),
                got: vec![t, p, c],
            });
        }
    }
    Ok(frames)
}

impl PerformerTrack {
    /// The 2-D tracks in [`PerformerPart::ALL`] order, each `(T, points, 2)` pixels.
    pub fn new(px: [Array3<f32>; 4]) -> Result<Self> {
        check(&px, 2, None)?;
        Ok(Self { px, metres: None })
    }

    /// Adds the 3-D tracks, each `(T, points, 3)` metres, same `T`.
    pub fn with_3d(mut self, metres: [Array3<f32>; 4]) -> Result<Self> {
        check(&metres, 3, Some(self.len()))?;
        self.metres = Some(metres);
        Ok(self)
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.px[0].len_of(Axis(0))
    }

    /// True when there are no frames.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// A part's 2-D track, pixels.
    pub fn track(&self, part: PerformerPart) -> &Array3<f32> {
        &self.px[part as usize]
    }

    /// A part's 3-D track, metres, when present.
    pub fn track_3d(&self, part: PerformerPart) -> Option<&Array3<f32>> {
        self.metres.as_ref().map(|m| &m[part as usize])
    }

    /// All 2-D tracks, mutable (their shapes cannot change).
    pub fn tracks_mut(&mut self) -> impl Iterator<Item = ndarray::ArrayViewMut3<'_, f32>> {
        self.px.iter_mut().map(|a| a.view_mut())
    }

    /// Largest coefficient of variation of a bone's length over time, over every part's
    /// bones (3-D when present, else the 2-D projections).
    pub fn max_bone_length_cv(&self) -> f32 {
        let mut worst = 0.0f32;
        for part in PerformerPart::ALL {
            let track = self.track_3d(part).unwrap_or(self.track(part));
            for (a, b) in part.bones() {
                let lengths: Vec<f64> = track
                    .axis_iter(Axis(0))
                    .map(|f| {
                        (0..f.dim().1)
                            .map(|c| f64::from(f[[a, c]] - f[[b, c]]).powi(2))
                            .sum::<f64>()
                            .sqrt()
                    })
                    .collect();
                worst = worst.max(coefficient_of_variation(&lengths));
            }
        }
        worst
    }

    /// Mean 2-D acceleration of the hand points (both hands), pixels / frame².
    pub fn hand_jitter_px(&self) -> f32 {
        let mut all = jitter_per_joint(self.track(PerformerPart::LeftHand));
        all.extend(jitter_per_joint(self.track(PerformerPart::RightHand)));
        all.iter().sum::<f32>() / all.len().max(1) as f32
    }
}

fn coefficient_of_variation(values: &[f64]) -> f32 {
    let n = values.len().max(1) as f64;
    let mean = values.iter().sum::<f64>() / n;
    if mean <= 1e-12 {
        return 0.0;
    }
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    (var.sqrt() / mean) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn zeros(t: usize, dims: usize) -> [Array3<f32>; 4] {
        PerformerPart::ALL.map(|p| Array3::zeros((t, p.point_count(), dims)))
    }

    #[test]
    fn shapes_are_checked() {
        let ok = PerformerTrack::new(zeros(3, 2)).unwrap();
        assert!(ok.clone().with_3d(zeros(4, 3)).is_err());
        assert!(ok.with_3d(zeros(3, 3)).is_ok());
        let mut bad = zeros(3, 2);
        bad[1] = Array3::zeros((3, 20, 2));
        assert!(PerformerTrack::new(bad).is_err());
    }

    #[test]
    fn stretching_a_bone_shows_in_the_cv_and_moving_a_hand_in_the_jitter() {
        let mut px = zeros(4, 2);
        for t in 0..4 {
            px[1][[t, 20, 0]] = 1.0 + (t % 2) as f32; // the pinky tip jumps
        }
        let track = PerformerTrack::new(px).unwrap();
        assert!(track.max_bone_length_cv() > 0.1);
        assert!(track.hand_jitter_px() > 0.0);
        assert_eq!(
            PerformerTrack::new(zeros(4, 2)).unwrap().hand_jitter_px(),
            0.0
        );
    }
}
