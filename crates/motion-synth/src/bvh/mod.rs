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
//! Every joint but the root has `CHANNELS 3 Zrotation Xrotation Yrotation` (the rotation is
//! `Rz · Rx · Ry`). OFFSETs are the skeleton's bone lengths (mean over the motion, which for
//! a synthesised motion are the [`crate::Rig`]'s); the rest pose stands upright with the
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
//! use motion_synth::{bvh, synthesize, SynthConfig};
//! use performance::Performance;
//! let perf = Performance::builder(1.0).note(0.0, 1.0, 69).build()?;
//! let motion = synthesize(&perf, &SynthConfig::default())?;
//! let mut text = Vec::new();
//! bvh::write_bvh(&motion, &mut text)?;
//! let parsed = bvh::parse_bvh(std::str::from_utf8(&text).unwrap())?;
//! assert_eq!(parsed.frames.len(), 30);
//! assert_eq!(parsed.channel_count(), 6 + 11 * 3);
//! # Ok::<(), motion_synth::SynthError>(())
//! ```

mod parse;
mod write;

pub use parse::{parse_bvh, Bvh, BvhJoint, Channel};
pub use write::{joint_for, write_bvh, write_bvh_file, BVH_JOINTS};
