//! The small 3-D vector and rotation types of the rig, which live in `skeleton`
//! ([`skeleton::geometry`]: metres, x to the player's left, y up, z forward).

pub use skeleton::geometry::{smoothstep, Mat3, Transform, Vec3};
