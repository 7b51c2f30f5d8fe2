//! # motion-synth
//!
//! Turns a [`performance::Performance`] — what is played when, and how — into a violinist skeleton
//! ([`skeleton::Motion`], 30 fps): the spine of the product is *analysis → Performance →
//! motion* (ARCHITECTURE.md), and this crate is its last arrow (SPEC §5–7).
//!
//! * **Right arm** ([`bow`]): bow changes become strokes that reverse at each change; the
//!   original rule (full bow = 28 frames, partial bow under 15 frames) is planned with
//!   look-ahead so the bow never leaves the frog–tip range, with eased strokes. Two-link IK
//!   ([`ik`]) puts the wrist on the frog while the bow crosses the bowed string (the arm is
//!   highest for G, lowest for E).
//! * **Left arm** ([`left_hand`]): each note's fingering ([`fingering`]) places the wrist on
//!   the neck, gliding 100 ms into shifts; string crossings glide too.
//! * **Body** ([`body`]): arousal (2 Hz, monotone-cubic to 30 fps) tilts the torso (back
//!   when excited, forward when calm); the head sways once per bar, forward on downbeats,
//!   with extent and speed from the bar's arousal.
//! * **Rig and camera** ([`Rig`], [`Camera`]): an adult body, the violin on the left
//!   shoulder pointing forward-left, a 0.75 m bow, seen by a pinhole camera (1280×720,
//!   in front, slightly to the player's right). Bone lengths are constant by construction.
//! * **Exports and checks**: [`bvh`] (Blender-readable BVH, plus a parser with forward
//!   kinematics), [`metrics`] (bow-range violations, bone-length variation, jitter, beat
//!   alignment).
//!
//! ```
//! use motion_synth::{metrics, synthesize_detailed, SynthConfig};
//! use performance::{ArousalCurve, Performance};
//! let perf = Performance::builder(4.0)
//!     .note(0.0, 1.0, 67).note(1.0, 2.0, 69).note(2.0, 3.0, 71).note(3.0, 4.0, 72)
//!     .bow_changes(vec![1.0, 2.0, 3.0])
//!     .beats(vec![0.0, 1.0, 2.0, 3.0])
//!     .downbeats(vec![0.0, 2.0])
//!     .arousal(ArousalCurve::deam(vec![-0.5, -0.2, 0.0, 0.3, 0.5, 0.6, 0.7, 0.8]))
//!     .build()?;
//! let out = synthesize_detailed(&perf, &SynthConfig::default())?;
//! assert_eq!(out.motion.len(), 120);
//! assert_eq!(metrics::bow_range_violations(out.bow.positions()), 0.0);
//! assert!(out.motion.max_bone_length_cv() < 1e-4);
//! # Ok::<(), motion_synth::SynthError>(())
//! ```

pub mod body;
pub mod bow;
mod bow_profile;
mod bow_stroke;
pub use skeleton::formats::bvh;
mod camera;
pub mod contact;
mod error;
pub mod geometry;
pub mod hands;
pub mod ik;
pub mod interp;
pub mod left_hand;
pub mod metrics;
pub mod performer;
mod rig;
mod synth;
pub mod violin;

pub use body::BodyConfig;
pub use bow::{BowDirection, BowPlan, BowPolicy, PlannedStroke};
pub use camera::Camera;
pub use error::{Result, SynthError};
pub use left_hand::LeftHandConfig;
pub use rig::{BowGeometry, Pose, PoseInput, PoseParts, Rig, ViolinGeometry};
pub use synth::{synthesize, synthesize_detailed, SynthConfig, Synthesis};

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
