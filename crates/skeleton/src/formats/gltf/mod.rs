//! glTF 2.0 binary (`.glb`) export: a node hierarchy whose translations are animated.
//!
//! Two layers:
//! * [`NodeAnimation`]: a generic description — named nodes with parents and a world position
//!   per frame, `(T, N, 3)` metres at an fps — written by [`glb_bytes`] / [`write_glb`] as
//!   one node per entry (translation = own world position − parent's; the first frame is the
//!   rest pose), one animation with a LINEAR translation sampler per node over a shared time
//!   accessor (with min/max), two buffer views (times, translations) in one BIN chunk.
//! * [`motion_animation`]: a [`crate::Motion`]'s 3-D track and 3-D instrument points laid out
//!   by the table [`MOTION_NODES`] (root → hips → neck → head, shoulders → elbows → wrists,
//!   a `bow` under the right wrist and a `violin` under the root). More points become more
//!   rows of that table.
//!
//! Coordinates stay as the motion has them: metres, y up, the player facing +z, which is
//! glTF's own convention (Blender's importer turns y-up into z-up).
//!
//! ```
//! use ndarray::Array3;
//! use skeleton::formats::gltf::{glb_bytes, AnimNode, NodeAnimation};
//! let nodes = vec![
//!     AnimNode { name: "root".into(), parent: None },
//!     AnimNode { name: "hand".into(), parent: Some(0) },
//! ];
//! let anim = NodeAnimation::new(nodes, 30.0, Array3::from_elem((3, 2, 3), 0.5))?;
//! let bytes = glb_bytes(&anim, "demo")?;
//! assert_eq!(&bytes[..4], b"glTF");
//! assert_eq!(bytes.len() % 4, 0);
//! # Ok::<(), skeleton::SkeletonError>(())
//! ```

mod animation;
mod glb;
mod motion_nodes;

pub use animation::{AnimNode, NodeAnimation};
pub use glb::{glb_bytes, write_glb, CHUNK_BIN, CHUNK_JSON, GLB_MAGIC};
pub use motion_nodes::{
    motion_animation, motion_animation_with, NodeSource, NodeSpec, MOTION_NODES,
};

use std::io::Write;

use crate::error::Result;
use crate::motion::Motion;

/// The scene and animation name in files written from a motion.
pub(crate) const MOTION_NAME: &str = "violinist";

/// What a motion's GLB animates: the whole performer (BODY_25 body, every finger joint,
/// `Violin` and `Bow` with their parts; the BVH's hierarchy and names, 83 nodes) when the
/// motion has its 3-D tracks, else the core joints by [`motion_animation`]; fails without a
/// 3-D track.
pub fn motion_glb_animation(motion: &Motion) -> Result<NodeAnimation> {
    let performer = motion
        .performer()
        .and_then(crate::formats::bvh::performer_hierarchy);
    match performer {
        Some((joints, positions)) if !motion.is_empty() => {
            let nodes = joints
                .into_iter()
                .map(|(name, parent)| AnimNode { name, parent })
                .collect();
            NodeAnimation::new(nodes, motion.fps(), positions)
        }
        _ => motion_animation(motion),
    }
}

/// Writes `motion` as GLB to `out` (see [`motion_glb_animation`]).
pub fn write_motion_glb(motion: &Motion, out: impl Write) -> Result<()> {
    write_glb(&motion_glb_animation(motion)?, MOTION_NAME, out)
}
