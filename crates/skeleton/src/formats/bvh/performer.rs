//! BVH of the whole performer: BODY_25 body, both hands with every finger joint, and the
//! violin and the bow as joints of their own.
//!
//! The rest pose (the OFFSETs) is the performer's first frame with every joint unrotated, so
//! Blender shows the player standing with the violin up; y is up, the player faces +z,
//! units are centimetres. Each joint's rotation comes from a frame of two of its points
//! (the direction to its first child and a second point fixing the twist): its world
//! rotation is that frame now times the same frame in the first frame, transposed. The
//! violin and the bow are rigid objects with position channels of their own; leaves
//! (fingertips, toes, eyes, string ends) have zero rotations. For a rig whose segments are
//! rigid (as `motion-synth` makes them), forward kinematics reproduces every point.

use std::io::Write;

use ndarray::Array3;

use super::euler::euler_zxy;
use crate::body25::BodyPoint;
use crate::error::{Result, SkeletonError};
use crate::geometry::{Mat3, Vec3};
use crate::hand::Finger;
use crate::instrument_parts::InstrumentPart;
use crate::motion::Motion;
use crate::performer::{PerformerPart, PerformerTrack};

const CM: f64 = 100.0;

/// Where a BVH joint sits.
#[derive(Debug, Clone, Copy)]
enum Pt {
    Body(BodyPoint),
    Hand(PerformerPart, usize),
    Inst(InstrumentPart),
    Mid(BodyPoint, BodyPoint),
}

/// One joint: name, parent, position, the two points of its frame (`None`: a leaf that
/// turns with its parent), and whether it has position channels.
struct Node {
    name: String,
    parent: Option<usize>,
    at: Pt,
    frame: Option<(Pt, Pt)>,
    moves: bool,
}

struct Builder(Vec<Node>);

impl Builder {
    fn add(&mut self, name: &str, parent: Option<usize>, at: Pt, frame: Option<(Pt, Pt)>) -> usize {
        self.0.push(Node {
            name: name.to_string(),
            parent,
            at,
            frame,
            moves: false,
        });
        self.0.len() - 1
    }
}

fn leg(b: &mut Builder, root: usize, side: &str, right: bool) {
    use BodyPoint::*;
    let [hip, knee, ankle, big, small, heel] = if right {
        [RHip, RKnee, RAnkle, RBigToe, RSmallToe, RHeel]
    } else {
        [LHip, LKnee, LAnkle, LBigToe, LSmallToe, LHeel]
    };
    let p = Pt::Body;
    let up = b.add(
        &format!("{side}UpLeg"),
        Some(root),
        p(hip),
        Some((p(knee), p(big))),
    );
    let lo = b.add(
        &format!("{side}Leg"),
        Some(up),
        p(knee),
        Some((p(ankle), p(big))),
    );
    let foot = b.add(
        &format!("{side}Foot"),
        Some(lo),
        p(ankle),
        Some((p(big), p(heel))),
    );
    b.add(&format!("{side}BigToe"), Some(foot), p(big), None);
    b.add(&format!("{side}SmallToe"), Some(foot), p(small), None);
    b.add(&format!("{side}Heel"), Some(foot), p(heel), None);
}

fn arm(b: &mut Builder, spine: usize, side: &str, right: bool) {
    use BodyPoint::*;
    let [sh, el, wr] = if right {
        [RShoulder, RElbow, RWrist]
    } else {
        [LShoulder, LElbow, LWrist]
    };
    let hand = if right {
        PerformerPart::RightHand
    } else {
        PerformerPart::LeftHand
    };
    let p = Pt::Body;
    let h = |k: usize| Pt::Hand(hand, k);
    let s = b.add(
        &format!("{side}Shoulder"),
        Some(spine),
        p(sh),
        Some((p(el), p(wr))),
    );
    let e = b.add(
        &format!("{side}Elbow"),
        Some(s),
        p(el),
        Some((p(wr), p(sh))),
    );
    let index = Finger::Index.point(1);
    let pinky = Finger::Pinky.point(1);
    let w = b.add(
        &format!("{side}Wrist"),
        Some(e),
        p(wr),
        Some((h(index), h(pinky))),
    );
    for f in Finger::ALL {
        let mut parent = w;
        for k in 1..=4 {
            let title = f.name()[..1].to_ascii_uppercase() + &f.name()[1..];
            let frame = (k < 4).then(|| {
                (
                    h(f.point(k + 1)),
                    h(if k < 3 { f.point(4) } else { f.point(2) }),
                )
            });
            parent = b.add(
                &format!("{side}Hand{title}{k}"),
                Some(parent),
                h(f.point(k)),
                frame,
            );
        }
    }
}

/// The joint table, parents before children.
fn skeleton() -> Vec<Node> {
    use BodyPoint::*;
    let mut b = Builder(Vec::with_capacity(96));
    let p = Pt::Body;
    let root = b.add("Hips", None, p(MidHip), Some((p(LHip), p(Neck))));
    leg(&mut b, root, "Right", true);
    leg(&mut b, root, "Left", false);
    let spine = b.add(
        "Spine",
        Some(root),
        Pt::Mid(MidHip, Neck),
        Some((p(Neck), p(LShoulder))),
    );
    let neck = b.add("Neck", Some(spine), p(Neck), Some((p(Nose), p(LEar))));
    for (name, point) in [
        ("Nose", Nose),
        ("RightEye", REye),
        ("LeftEye", LEye),
        ("RightEar", REar),
        ("LeftEar", LEar),
    ] {
        b.add(name, Some(neck), p(point), None);
    }
    arm(&mut b, spine, "Right", true);
    arm(&mut b, spine, "Left", false);
    use InstrumentPart as I;
    let violin = b.add(
        "Violin",
        Some(root),
        Pt::Inst(I::ViolinEndButton),
        Some((Pt::Inst(I::ViolinScroll), Pt::Inst(I::StringAtBridge(0)))),
    );
    b.0[violin].moves = true;
    for part in I::ALL
        .into_iter()
        .filter(|q| !q.is_bow() && *q != I::ViolinEndButton)
    {
        b.add(&camel(part.name()), Some(violin), Pt::Inst(part), None);
    }
    let bow = b.add(
        "Bow",
        Some(root),
        Pt::Inst(I::BowFrog),
        Some((Pt::Inst(I::BowTip), Pt::Inst(I::BowHairFrog))),
    );
    b.0[bow].moves = true;
    for part in [I::BowTip, I::BowHairFrog, I::BowHairTip] {
        b.add(&camel(part.name()), Some(bow), Pt::Inst(part), None);
    }
    b.0
}

/// `violin_end_button` → `ViolinEndButton`.
fn camel(name: &str) -> String {
    name.split('_')
        .map(|w| w[..1].to_ascii_uppercase() + &w[1..])
        .collect()
}

fn get(track: &Array3<f32>, f: usize, i: usize) -> Vec3 {
    Vec3::new(
        f64::from(track[[f, i, 0]]),
        f64::from(track[[f, i, 1]]),
        f64::from(track[[f, i, 2]]),
    )
}

/// World position (metres) of `pt` at frame `f`.
fn position(tracks: &[&Array3<f32>; 4], pt: Pt, f: usize) -> Vec3 {
    match pt {
        Pt::Body(b) => get(tracks[0], f, b.index()),
        Pt::Hand(part, k) => get(tracks[part as usize], f, k),
        Pt::Inst(i) => get(tracks[3], f, i.index()),
        Pt::Mid(a, b) => (get(tracks[0], f, a.index()) + get(tracks[0], f, b.index())) * 0.5,
    }
}

fn frame_of(tracks: &[&Array3<f32>; 4], node: &Node, f: usize) -> Option<Mat3> {
    let (a, b) = node.frame?;
    let o = position(tracks, node.at, f);
    let e1 = (position(tracks, a, f) - o).normalized_or(Vec3::X);
    let s = position(tracks, b, f) - o;
    let e2 = (s - e1 * s.dot(e1)).normalized_or(if e1.y.abs() < 0.9 { Vec3::Y } else { Vec3::Z });
    let e2 = (e2 - e1 * e2.dot(e1)).normalized_or(Vec3::Z);
    Some(Mat3::from_columns(e1, e2, e1.cross(e2)))
}

/// The BVH joints written for a performer, in file order.
pub fn performer_joint_names() -> Vec<String> {
    skeleton().into_iter().map(|n| n.name).collect()
}

/// A joint hierarchy with world positions: `(name, parent)` per joint, parents first, and
/// `(T, joints, 3)` metres.
pub type PerformerHierarchy = (Vec<(String, Option<usize>)>, Array3<f32>);

/// The performer's 3-D tracks laid out as the BVH's joints (names, parents) with their world
/// positions per frame — what the glTF writer animates when a motion has a performer;
/// `None` when a 3-D track is missing.
pub fn performer_hierarchy(performer: &PerformerTrack) -> Option<PerformerHierarchy> {
    let mut tracks: Vec<&Array3<f32>> = Vec::with_capacity(4);
    for part in PerformerPart::ALL {
        tracks.push(performer.track_3d(part)?);
    }
    let tracks: [&Array3<f32>; 4] = [tracks[0], tracks[1], tracks[2], tracks[3]];
    let nodes = skeleton();
    let frames = performer.len();
    let mut positions = Array3::<f32>::zeros((frames, nodes.len(), 3));
    for f in 0..frames {
        for (i, node) in nodes.iter().enumerate() {
            let p = position(&tracks, node.at, f);
            positions[[f, i, 0]] = p.x as f32;
            positions[[f, i, 1]] = p.y as f32;
            positions[[f, i, 2]] = p.z as f32;
        }
    }
    let names = nodes.into_iter().map(|n| (n.name, n.parent)).collect();
    Some((names, positions))
}

/// Writes the performer's 3-D tracks as BVH (see the module documentation).
pub(super) fn write_performer_bvh(
    motion: &Motion,
    performer: &PerformerTrack,
    mut out: impl Write,
) -> Result<()> {
    let missing = SkeletonError::MissingTrack {
        track: "performer 3-D track",
        hint: "synthesize the motion with motion-synth",
    };
    let mut parts = Vec::with_capacity(4);
    for part in PerformerPart::ALL {
        parts.push(
            performer
                .track_3d(part)
                .ok_or(SkeletonError::MissingTrack {
                    track: "performer 3-D track",
                    hint: "synthesize the motion with motion-synth",
                })?,
        );
    }
    let tracks: [&Array3<f32>; 4] = [parts[0], parts[1], parts[2], parts[3]];
    if tracks.iter().any(|t| t.iter().any(|v| !v.is_finite())) {
        return Err(SkeletonError::MissingTrack {
            track: "finite performer 3-D coordinates",
            hint: "the performer's 3-D track contains NaN or infinity",
        });
    }
    let n = motion.len();
    if n == 0 {
        return Err(missing);
    }
    let nodes = skeleton();
    let rest: Vec<Option<Mat3>> = nodes
        .iter()
        .map(|node| frame_of(&tracks, node, 0))
        .collect();
    let offsets: Vec<Vec3> = nodes
        .iter()
        .map(|node| match node.parent {
            Some(p) => (position(&tracks, node.at, 0) - position(&tracks, nodes[p].at, 0)) * CM,
            None => Vec3::ZERO,
        })
        .collect();
    let mut children = vec![0usize; nodes.len()];
    for node in &nodes {
        if let Some(p) = node.parent {
            children[p] += 1;
        }
    }
    // Hierarchy.
    let mut h = String::with_capacity(16 * 1024);
    h.push_str("HIERARCHY\n");
    let fmt = |v: Vec3| format!("OFFSET {:.4} {:.4} {:.4}", v.x, v.y, v.z);
    let mut open: Vec<usize> = Vec::new();
    for (i, node) in nodes.iter().enumerate() {
        while open.last().is_some_and(|&top| Some(top) != node.parent) {
            open.pop();
            h.push_str(&format!("{}}}\n", "\t".repeat(open.len())));
        }
        let tabs = "\t".repeat(open.len());
        let kind = if node.parent.is_none() {
            "ROOT"
        } else {
            "JOINT"
        };
        let channels = if node.parent.is_none() || node.moves {
            "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"
        } else {
            "CHANNELS 3 Zrotation Xrotation Yrotation"
        };
        h.push_str(&format!(
            "{tabs}{kind} {}\n{tabs}{{\n{tabs}\t{}\n{tabs}\t{channels}\n",
            node.name,
            fmt(offsets[i])
        ));
        if children[i] == 0 {
            let tip = offsets[i].normalized_or(Vec3::Y) * 2.0;
            h.push_str(&format!(
                "{tabs}\tEnd Site\n{tabs}\t{{\n{tabs}\t\t{}\n{tabs}\t}}\n{tabs}}}\n",
                fmt(tip)
            ));
        } else {
            open.push(i);
        }
    }
    while open.pop().is_some() {
        h.push_str(&format!("{}}}\n", "\t".repeat(open.len())));
    }
    h.push_str(&format!(
        "MOTION\nFrames: {n}\nFrame Time: {:.7}\n",
        1.0 / motion.fps()
    ));
    out.write_all(h.as_bytes())?;

    let mut world = vec![Mat3::IDENTITY; nodes.len()];
    let mut row: Vec<f64> = Vec::with_capacity(nodes.len() * 3 + 12);
    let mut prev: Vec<f64> = Vec::new();
    let mut is_angle: Vec<bool> = Vec::with_capacity(nodes.len() * 3 + 12);
    let mut text = String::with_capacity(4096);
    for f in 0..n {
        row.clear();
        for (i, node) in nodes.iter().enumerate() {
            let parent_world = node.parent.map_or(Mat3::IDENTITY, |p| world[p]);
            world[i] = match (frame_of(&tracks, node, f), rest[i]) {
                (Some(now), Some(r)) => now * r.transpose(),
                _ => parent_world,
            };
            let here = position(&tracks, node.at, f) * CM;
            match node.parent {
                None => row.extend(here.to_array()),
                Some(p) if node.moves => {
                    let local =
                        parent_world.transpose() * (here - position(&tracks, nodes[p].at, f) * CM);
                    row.extend((local - offsets[i]).to_array());
                }
                Some(_) => {}
            }
            if f == 0 {
                is_angle.resize(row.len(), false);
                is_angle.extend([true; 3]);
            }
            row.extend(euler_zxy(&(parent_world.transpose() * world[i])));
        }
        // Keep each angle within 180° of the previous frame's (same rotation, no wrap jumps).
        if prev.len() == row.len() {
            for ((v, q), angle) in row.iter_mut().zip(&prev).zip(&is_angle) {
                if *angle {
                    *v -= 360.0 * ((*v - q) / 360.0).round();
                }
            }
        }
        super::fixed::write_frame_line(&mut out, &mut text, &row)?;
        prev.clone_from(&row);
    }
    out.flush()?;
    Ok(())
}
