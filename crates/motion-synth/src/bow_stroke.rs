//! The vocabulary of the bow planner ([`crate::bow`]): its rules, a stroke's direction and a
//! planned stroke.

use crate::error::{Result, SynthError};
pub use performance::BowDirection;

/// Rules of the bow planner; [`BowPolicy::default`] is the original design's rule.
#[derive(Debug, Clone, PartialEq)]
pub struct BowPolicy {
    /// Frames for a full bow at the normal speed (28 at 30 fps).
    pub full_bow_frames: usize,
    /// Strokes shorter than this many frames use a partial bow of their own length (15).
    pub partial_below_frames: usize,
    /// Fastest allowed stroke, in multiples of the full-bow speed (2.0).
    pub max_speed_factor: f64,
    /// Grid steps of the bow position in the planner (100: 1 % of the bow).
    pub resolution: usize,
    /// Cost of starting away from the preferred end, per bow length (0.5).
    pub start_weight: f64,
    /// Choose the first direction so that downbeats fall on down-bows (true).
    pub prefer_down_on_downbeats: bool,
    /// Bow speed at a reversal, as a fraction of the stroke's cruise speed (0.25).
    pub reversal_speed: f64,
    /// Share of the stroke spent accelerating (and, at the end, decelerating) (0.25).
    pub ramp_fraction: f64,
}

impl Default for BowPolicy {
    fn default() -> Self {
        BowPolicy {
            full_bow_frames: 28,
            partial_below_frames: 15,
            max_speed_factor: 2.0,
            resolution: 100,
            start_weight: 0.5,
            prefer_down_on_downbeats: true,
            reversal_speed: 0.25,
            ramp_fraction: 0.25,
        }
    }
}

impl BowPolicy {
    pub(crate) fn validate(&self) -> Result<()> {
        let ok = self.full_bow_frames > 0
            && self.resolution >= 4
            && self.resolution <= 10_000
            && self.max_speed_factor.is_finite()
            && self.max_speed_factor >= 1.0
            && self.start_weight.is_finite()
            && self.start_weight >= 0.0
            && (0.0..=1.0).contains(&self.reversal_speed)
            && (0.0..=0.5).contains(&self.ramp_fraction);
        if ok {
            Ok(())
        } else {
            Err(SynthError::InvalidConfig(format!(
                "bow policy {self:?}: need full_bow_frames > 0, resolution 4..=10000, \
                 max_speed_factor >= 1, start_weight >= 0, reversal_speed in [0, 1], ramp_fraction in [0, 0.5]"
            )))
        }
    }

    /// The original rule's travel for a stroke of `frames` frames, in bow lengths.
    pub fn desired_travel(&self, frames: usize) -> f64 {
        if frames < self.partial_below_frames {
            (frames as f64 / self.full_bow_frames as f64).min(1.0)
        } else {
            1.0
        }
    }
}

/// One stroke of a [`crate::BowPlan`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PlannedStroke {
    /// First frame.
    pub start_frame: usize,
    /// One past the last frame (the next stroke's first frame).
    pub end_frame: usize,
    /// Direction.
    pub direction: BowDirection,
    /// Bow position at `start_frame` (0 frog … 1 tip).
    pub start_position: f64,
    /// Bow position at `end_frame`.
    pub end_position: f64,
    /// What the original rule asked for, bow lengths.
    pub desired_travel: f64,
}
