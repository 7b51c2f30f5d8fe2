//! # skeleton
//!
//! The shared vocabulary of motion in violin-skeleton: the ten [`Joint`]s of the violinist
//! (with OpenPose COCO-18 / BODY_25 index maps), [`Motion`] (joint tracks at a frame rate,
//! optional 3-D and instrument tracks, and the whole [`PerformerTrack`]: BODY_25 body
//! ([`BodyPoint`]), 21-point hands ([`Finger`]), violin and bow ([`InstrumentPart`])), [`BONES`], plausibility metrics, motion files
//! ([`formats`], BVH included: [`formats::bvh`]) and the small 3-D [`geometry`] they use.
//!
//! ```
//! use ndarray::Array3;
//! use skeleton::{Joint, Motion, PoseLayout};
//! let motion = Motion::new(30.0, Array3::zeros((30, 10, 2)))?;
//! assert_eq!(motion.jitter(), 0.0);
//! assert_eq!(Joint::LWrist.openpose_index(PoseLayout::Body25), 7);
//! # Ok::<(), skeleton::SkeletonError>(())
//! ```

mod body25;
pub mod canvas;
mod error;
pub mod formats;
pub mod geometry;
mod hand;
mod instrument_parts;
mod joint;
pub mod metrics;
mod motion;
mod performer;

pub use body25::{BodyPoint, BODY25_BONES, BODY25_COUNT};
pub use canvas::Canvas;
pub use error::{Result, SkeletonError};
pub use formats::{MotionFormat, OpenPoseOptions};
pub use hand::{Finger, HAND_BONES, HAND_POINT_COUNT, HAND_POINT_NAMES};
pub use instrument_parts::{InstrumentPart, INSTRUMENT_BONES, INSTRUMENT_PART_COUNT};
pub use joint::{Joint, PoseLayout, BONES, JOINT_COUNT};
pub use motion::{InstrumentPoint, Motion};
pub use performer::{PerformerPart, PerformerTrack};
