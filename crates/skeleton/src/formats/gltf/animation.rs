//! The generic description a GLB is written from: named nodes in a hierarchy, each with a
//! world position per frame. Nothing here knows about violinists.

use ndarray::Array3;

use crate::error::{Result, SkeletonError};

/// One node of a [`NodeAnimation`]: a name and the index of its parent (`None` for a root).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AnimNode {
    /// The node's name in the file (unique within the animation).
    pub name: String,
    /// Index of the parent node in [`NodeAnimation::nodes`]; parents come before children.
    pub parent: Option<usize>,
}

/// Named nodes in a hierarchy with a world position per frame: `positions[t, n, c]` is
/// coordinate `c` (x, y, z in metres; y up) of node `n` at frame `t`, at `fps` frames per
/// second.
///
/// Built with [`NodeAnimation::new`], which checks that every parent comes before its
/// children (so the hierarchy has no cycles), that names are unique and non-empty, and that
/// the positions have one row per node and are finite.
///
/// ```
/// use ndarray::Array3;
/// use skeleton::formats::gltf::{AnimNode, NodeAnimation};
/// let nodes = vec![
///     AnimNode { name: "root".into(), parent: None },
///     AnimNode { name: "tip".into(), parent: Some(0) },
/// ];
/// let anim = NodeAnimation::new(nodes, 30.0, Array3::zeros((5, 2, 3)))?;
/// assert_eq!(anim.frame_count(), 5);
/// assert_eq!(anim.children(0), vec![1]);
/// # Ok::<(), skeleton::SkeletonError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct NodeAnimation {
    nodes: Vec<AnimNode>,
    fps: f64,
    positions: Array3<f32>,
}

fn invalid(reason: String) -> SkeletonError {
    SkeletonError::InvalidAnimation { reason }
}

impl NodeAnimation {
    /// Checks and wraps a description; `positions` must be `(T, nodes.len(), 3)` with
    /// `T ≥ 1`, all finite.
    pub fn new(nodes: Vec<AnimNode>, fps: f64, positions: Array3<f32>) -> Result<Self> {
        if !(fps.is_finite() && fps > 0.0) {
            return Err(SkeletonError::InvalidFps(fps));
        }
        let (t, n, c) = positions.dim();
        if n != nodes.len() || c != 3 || t == 0 {
            return Err(SkeletonError::Shape {
                expected: format!("(frames ≥ 1, {}, 3)", nodes.len()),
                got: vec![t, n, c],
            });
        }
        if nodes.is_empty() {
            return Err(invalid("no nodes".into()));
        }
        for (i, node) in nodes.iter().enumerate() {
            if node.name.is_empty() {
                return Err(invalid(format!("node {i} has an empty name")));
            }
            if nodes[..i].iter().any(|m| m.name == node.name) {
                return Err(invalid(format!("node name {:?} is used twice", node.name)));
            }
            if let Some(p) = node.parent {
                if p >= i {
                    return Err(invalid(format!(
                        "node {:?} (index {i}) has parent index {p}; a parent must come before its children",
                        node.name
                    )));
                }
            }
        }
        if let Some(((f, j, k), v)) = positions.indexed_iter().find(|(_, v)| !v.is_finite()) {
            return Err(invalid(format!(
                "frame {f}, node {:?}, coordinate {} is {v}; positions must be finite",
                nodes[j].name,
                ["x", "y", "z"][k]
            )));
        }
        Ok(Self {
            nodes,
            fps,
            positions,
        })
    }

    /// The nodes, parents before children.
    pub fn nodes(&self) -> &[AnimNode] {
        &self.nodes
    }

    /// Frames per second.
    pub fn fps(&self) -> f64 {
        self.fps
    }

    /// Number of frames (at least 1).
    pub fn frame_count(&self) -> usize {
        self.positions.dim().0
    }

    /// World positions `(T, N, 3)`, metres.
    pub fn positions(&self) -> &Array3<f32> {
        &self.positions
    }

    /// Indices of the nodes whose parent is `node`, in order.
    pub fn children(&self, node: usize) -> Vec<usize> {
        (0..self.nodes.len())
            .filter(|&i| self.nodes[i].parent == Some(node))
            .collect()
    }

    /// Indices of the root nodes (no parent), in order.
    pub fn roots(&self) -> Vec<usize> {
        (0..self.nodes.len())
            .filter(|&i| self.nodes[i].parent.is_none())
            .collect()
    }

    /// Node `node`'s translation relative to its parent at frame `frame`: its world position
    /// minus its parent's (a root's is its world position).
    ///
    /// # Panics
    /// When `frame` or `node` is out of range, like slice indexing.
    pub fn local_translation(&self, frame: usize, node: usize) -> [f32; 3] {
        let own = self.world(frame, node);
        match self.nodes[node].parent {
            None => own,
            Some(parent) => {
                let up = self.world(frame, parent);
                [own[0] - up[0], own[1] - up[1], own[2] - up[2]]
            }
        }
    }

    /// Node `node`'s world position at frame `frame` (panics when out of range).
    pub fn world(&self, frame: usize, node: usize) -> [f32; 3] {
        let p = &self.positions;
        [
            p[[frame, node, 0]],
            p[[frame, node, 1]],
            p[[frame, node, 2]],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(name: &str, parent: Option<usize>) -> AnimNode {
        AnimNode {
            name: name.into(),
            parent,
        }
    }

    #[test]
    fn bad_descriptions_are_refused_with_a_reason() {
        let z = |n| Array3::<f32>::zeros((2, n, 3));
        let err = NodeAnimation::new(vec![node("a", Some(1)), node("b", None)], 30.0, z(2));
        assert!(err.unwrap_err().to_string().contains("before its children"));
        let err = NodeAnimation::new(vec![node("a", None), node("a", Some(0))], 30.0, z(2));
        assert!(err.unwrap_err().to_string().contains("used twice"));
        assert!(NodeAnimation::new(vec![node("a", None)], 30.0, z(2)).is_err());
        assert!(NodeAnimation::new(vec![node("a", None)], 0.0, z(1)).is_err());
        assert!(NodeAnimation::new(vec![node("a", None)], 30.0, Array3::zeros((0, 1, 3))).is_err());
        let mut p = z(1);
        p[[1, 0, 2]] = f32::NAN;
        let err = NodeAnimation::new(vec![node("a", None)], 30.0, p).unwrap_err();
        assert!(err.to_string().contains("frame 1"), "{err}");
    }

    #[test]
    fn local_translation_is_relative_to_the_parent() {
        let mut p = Array3::<f32>::zeros((1, 2, 3));
        p[[0, 0, 1]] = 1.0;
        p[[0, 1, 1]] = 1.5;
        p[[0, 1, 0]] = -0.25;
        let anim = NodeAnimation::new(vec![node("a", None), node("b", Some(0))], 30.0, p).unwrap();
        assert_eq!(anim.local_translation(0, 0), [0.0, 1.0, 0.0]);
        assert_eq!(anim.local_translation(0, 1), [-0.25, 0.5, 0.0]);
        assert_eq!(anim.roots(), vec![0]);
    }
}
