//! BVH export of the 3-D skeleton (Biovision hierarchy, as Blender's importer reads it), and
//! a small parser with forward kinematics to check files.
//!
//! Hierarchy (names as written; units centimetres and degrees; y up, the player facing +z):
//!
//! ```text
//! Hips (root: Xposition Yposition Zposition Zrotation Xrotation Yrotation)
//! ├── RightHip ─ End Site            (the hip joints)
//! ├── LeftHip ─ End Site
//! └── Spine                          (half-way up the torso)
//!     ├── Neck ── Head ─ End Site    (Head sits at the nose)
//!     ├── RightShoulder ── RightElbow ── RightWrist ─ End Site
//!     └── LeftShoulder ── LeftElbow ── LeftWrist ─ End Site
//! ```
//!
//! A motion with a 3-D performer track (BODY_25 body, hands, violin and bow) is written
//! with a larger hierarchy instead: 83 joints with every finger joint, `Violin` and `Bow`
//! (see [`performer_joint_names`] and the `performer` module's notes on its rest pose).
//!
//! Every joint but the root has `CHANNELS 3 Zrotation Xrotation Yrotation` (the rotation is
//! `Rz · Rx · Ry`). OFFSETs are the skeleton's bone lengths (mean over the motion, which for
//! a motion synthesised by `motion-synth` are its rig's); the rest pose stands upright with the
//! arms straight out to the sides (T-pose). The root rotation is the torso's orientation
//! (from the hip line and the neck), the shoulders and elbows turn the arm segments onto the
//! measured directions keeping the elbow's bending plane as the segments' local x–y plane,
//! so an elbow is a pure hinge about its local z. Forward kinematics of a written file
//! reproduces the motion's 3-D joints (within 1 mm for a rig-made motion; see
//! [`Bvh::forward_kinematics`]). Checked by hand with Blender 3.4's importer (File → Import
//! → Motion Capture): 12 bones, every frame, the wrist where the motion puts it (Blender
//! turns y-up into z-up).
//!
//! ```
//! use ndarray::Array3;
//! use skeleton::formats::bvh;
//! use skeleton::{Joint, Motion};
//! // A player standing still for 30 frames (metres, y up, facing +z).
//! let pose = [
//!     (Joint::Nose, [0.0, 1.62, 0.08]),
//!     (Joint::Neck, [0.0, 1.45, 0.0]),
//!     (Joint::RShoulder, [-0.19, 1.42, 0.0]),
//!     (Joint::RElbow, [-0.25, 1.15, 0.1]),
//!     (Joint::RWrist, [-0.2, 1.0, 0.3]),
//!     (Joint::LShoulder, [0.19, 1.42, 0.0]),
//!     (Joint::LElbow, [0.3, 1.3, 0.25]),
//!     (Joint::LWrist, [0.1, 1.45, 0.4]),
//!     (Joint::RHip, [-0.1, 0.95, 0.0]),
//!     (Joint::LHip, [0.1, 0.95, 0.0]),
//! ];
//! let mut track = Array3::<f32>::zeros((30, 10, 3));
//! for f in 0..30 {
//!     for (joint, p) in pose {
//!         for (c, v) in p.iter().enumerate() {
//!             track[[f, joint.index(), c]] = *v;
//!         }
//!     }
//! }
//! let motion = Motion::new(30.0, Array3::zeros((30, 10, 2)))?.with_3d(track)?;
//! let mut text = Vec::new();
//! bvh::write_bvh(&motion, &mut text)?;
//! let parsed = bvh::parse_bvh(std::str::from_utf8(&text).expect("BVH is text"))?;
//! assert_eq!(parsed.frames.len(), 30);
//! assert_eq!(parsed.channel_count(), 6 + 11 * 3);
//! # Ok::<(), skeleton::SkeletonError>(())
//! ```

mod euler;
mod fixed;
mod parse;
mod performer;
mod write;

pub use parse::{parse_bvh, Bvh, BvhJoint, Channel};
pub use performer::{performer_hierarchy, performer_joint_names, PerformerHierarchy};
pub use write::{joint_for, write_bvh, write_bvh_file, BVH_JOINTS};
