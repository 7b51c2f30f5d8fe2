//! A [`Motion`] as a [`NodeAnimation`]: one table says which node sits where and under whom.
//!
//! A richer skeleton (more body points, hands, more instrument points) is added as a new
//! [`NodeSource`] variant reading its track and new rows in [`MOTION_NODES`]; rows whose track
//! the motion lacks are left out together with their descendants.

use ndarray::Array3;

use super::animation::{AnimNode, NodeAnimation};
use crate::error::{Result, SkeletonError};
use crate::joint::Joint;
use crate::motion::{InstrumentPoint, Motion};

/// Where a node's world position comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeSource {
    /// Fixed at the origin (on the floor under the player): the scene's root.
    Origin,
    /// A joint of the 3-D track.
    Joint(Joint),
    /// The midpoint of two joints of the 3-D track.
    Midpoint(Joint, Joint),
    /// A point of the 3-D instrument track (left out when the motion has none).
    Instrument(InstrumentPoint),
}

/// One row of [`MOTION_NODES`]: a node's name, its parent's name and its position's source.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeSpec {
    /// The node's name in the file.
    pub name: &'static str,
    /// The parent's name (`None`: a root); the parent's row comes earlier in the table.
    pub parent: Option<&'static str>,
    /// Where the node's world position comes from.
    pub source: NodeSource,
}

const fn spec(name: &'static str, parent: &'static str, source: NodeSource) -> NodeSpec {
    NodeSpec {
        name,
        parent: Some(parent),
        source,
    }
}

/// The node hierarchy of a motion in a GLB, parents first:
///
/// ```text
/// root (origin)
/// ├── hips (between r_hip and l_hip)
/// │   ├── r_hip, l_hip
/// │   └── neck
/// │       ├── head (at the nose)
/// │       ├── r_shoulder ── r_elbow ── r_wrist ── bow (at the frog) ── bow_tip
/// │       └── l_shoulder ── l_elbow ── l_wrist
/// └── violin (body, under the bridge) ── violin_scroll
/// ```
pub const MOTION_NODES: [NodeSpec; 16] = [
    NodeSpec {
        name: "root",
        parent: None,
        source: NodeSource::Origin,
    },
    spec(
        "hips",
        "root",
        NodeSource::Midpoint(Joint::RHip, Joint::LHip),
    ),
    spec("r_hip", "hips", NodeSource::Joint(Joint::RHip)),
    spec("l_hip", "hips", NodeSource::Joint(Joint::LHip)),
    spec("neck", "hips", NodeSource::Joint(Joint::Neck)),
    spec("head", "neck", NodeSource::Joint(Joint::Nose)),
    spec("r_shoulder", "neck", NodeSource::Joint(Joint::RShoulder)),
    spec("r_elbow", "r_shoulder", NodeSource::Joint(Joint::RElbow)),
    spec("r_wrist", "r_elbow", NodeSource::Joint(Joint::RWrist)),
    spec("l_shoulder", "neck", NodeSource::Joint(Joint::LShoulder)),
    spec("l_elbow", "l_shoulder", NodeSource::Joint(Joint::LElbow)),
    spec("l_wrist", "l_elbow", NodeSource::Joint(Joint::LWrist)),
    spec(
        "bow",
        "r_wrist",
        NodeSource::Instrument(InstrumentPoint::BowFrog),
    ),
    spec(
        "bow_tip",
        "bow",
        NodeSource::Instrument(InstrumentPoint::BowTip),
    ),
    spec(
        "violin",
        "root",
        NodeSource::Instrument(InstrumentPoint::ViolinBody),
    ),
    spec(
        "violin_scroll",
        "violin",
        NodeSource::Instrument(InstrumentPoint::ViolinScroll),
    ),
];

/// The world position of `source` at `frame`, or `None` when the motion lacks its track.
fn position(motion: &Motion, source: NodeSource, frame: usize) -> Option<[f32; 3]> {
    let at = |track: &Array3<f32>, i: usize| {
        [
            track[[frame, i, 0]],
            track[[frame, i, 1]],
            track[[frame, i, 2]],
        ]
    };
    match source {
        NodeSource::Origin => Some([0.0; 3]),
        NodeSource::Joint(j) => motion.frames_3d().map(|t| at(t, j.index())),
        NodeSource::Midpoint(a, b) => motion.frames_3d().map(|t| {
            let (p, q) = (at(t, a.index()), at(t, b.index()));
            [
                0.5 * (p[0] + q[0]),
                0.5 * (p[1] + q[1]),
                0.5 * (p[2] + q[2]),
            ]
        }),
        NodeSource::Instrument(p) => motion.instrument_3d().map(|t| at(t, p as usize)),
    }
}

/// The rows of `table` the motion has tracks for (a row whose parent is left out is left
/// out too), with parent indices resolved.
fn present_nodes(motion: &Motion, table: &[NodeSpec]) -> Result<(Vec<AnimNode>, Vec<NodeSource>)> {
    let mut nodes: Vec<AnimNode> = Vec::new();
    let mut sources = Vec::new();
    for row in table {
        if position(motion, row.source, 0).is_none() {
            continue;
        }
        let parent = match row.parent {
            None => None,
            Some(name) => match nodes.iter().position(|n| n.name == name) {
                Some(i) => Some(i),
                None if table.iter().any(|r| r.name == name) => continue,
                None => {
                    return Err(SkeletonError::InvalidAnimation {
                        reason: format!("node {:?} names an unknown parent {name:?}", row.name),
                    })
                }
            },
        };
        nodes.push(AnimNode {
            name: row.name.to_string(),
            parent,
        });
        sources.push(row.source);
    }
    Ok((nodes, sources))
}

/// `motion`'s 3-D track (and 3-D instrument points, when present) as a node animation laid
/// out by [`MOTION_NODES`]. Fails when the motion has no 3-D track or no frames.
pub fn motion_animation(motion: &Motion) -> Result<NodeAnimation> {
    motion_animation_with(motion, &MOTION_NODES)
}

/// Like [`motion_animation`] with another node table.
pub fn motion_animation_with(motion: &Motion, table: &[NodeSpec]) -> Result<NodeAnimation> {
    if motion.frames_3d().is_none() {
        return Err(SkeletonError::MissingTrack {
            track: "3-D track",
            hint: "glTF needs 3-D joints; make the motion with the rules method (motion-synth), or export .json/.csv/.npy",
        });
    }
    if motion.is_empty() {
        return Err(SkeletonError::MissingTrack {
            track: "frames",
            hint: "the motion is empty",
        });
    }
    let (nodes, sources) = present_nodes(motion, table)?;
    let mut positions = Array3::<f32>::zeros((motion.len(), nodes.len(), 3));
    for frame in 0..motion.len() {
        for (n, source) in sources.iter().enumerate() {
            let p = position(motion, *source, frame).unwrap_or([0.0; 3]);
            for (c, v) in p.into_iter().enumerate() {
                positions[[frame, n, c]] = v;
            }
        }
    }
    NodeAnimation::new(nodes, motion.fps(), positions)
}
