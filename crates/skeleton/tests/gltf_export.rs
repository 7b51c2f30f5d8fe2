//! A written GLB parsed back by hand: header, chunk lengths, the JSON document, and forward
//! kinematics of the animated translations reproducing the motion's 3-D points.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use gltf_json::accessor::{ComponentType, Type};
use gltf_json::animation::{Interpolation, Property};
use gltf_json::validation::Checked::Valid;
use gltf_json::Root;
use ndarray::{Array2, Array3, Axis};
use skeleton::formats::gltf::{CHUNK_BIN, CHUNK_JSON, GLB_MAGIC, MOTION_NODES};
use skeleton::{InstrumentPoint, Joint, Motion, MotionFormat, SkeletonError};

const FRAMES: usize = 47;

/// A moving player: every coordinate a different slow sinusoid around a plausible pose.
fn motion(with_instrument: bool) -> Motion {
    let wave = |f: usize, k: usize| 0.05 * ((f as f32 * 0.13) + k as f32 * 0.7).sin();
    let mut joints = Array3::<f32>::zeros((FRAMES, 10, 3));
    for ((f, j, c), v) in joints.indexed_iter_mut() {
        let base = [0.2 * j as f32 - 1.0, 0.9 + 0.07 * j as f32, 0.03 * j as f32][c];
        *v = base + wave(f, 3 * j + c);
    }
    let mut m = Motion::new(30.0, Array3::zeros((FRAMES, 10, 2)))
        .unwrap()
        .with_3d(joints)
        .unwrap();
    if with_instrument {
        let mut inst = Array3::<f32>::zeros((FRAMES, 4, 3));
        for ((f, p, c), v) in inst.indexed_iter_mut() {
            *v = [0.1, 1.3, 0.3][c] + 0.1 * p as f32 + wave(f, 40 + 3 * p + c);
        }
        m = m.with_instrument_3d(inst).unwrap();
    }
    m
}

struct Glb {
    root: Root,
    bin: Vec<u8>,
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

/// Parses a GLB, checking the container as the spec defines it.
fn parse(bytes: &[u8]) -> Glb {
    assert_eq!(u32_at(bytes, 0), GLB_MAGIC);
    assert_eq!(u32_at(bytes, 4), 2, "GLB version");
    assert_eq!(u32_at(bytes, 8) as usize, bytes.len(), "header length");
    let json_len = u32_at(bytes, 12) as usize;
    assert_eq!(u32_at(bytes, 16), CHUNK_JSON);
    assert_eq!(json_len % 4, 0);
    let json = &bytes[20..20 + json_len];
    let bin_at = 20 + json_len;
    let bin_len = u32_at(bytes, bin_at) as usize;
    assert_eq!(u32_at(bytes, bin_at + 4), CHUNK_BIN);
    assert_eq!(bin_len % 4, 0);
    assert_eq!(
        bin_at + 8 + bin_len,
        bytes.len(),
        "no bytes after the BIN chunk"
    );
    let root = Root::from_slice(json).unwrap();
    let declared = root.buffers[0].byte_length.0 as usize;
    assert!(
        declared <= bin_len && bin_len - declared < 4,
        "buffer length vs chunk"
    );
    Glb {
        root,
        bin: bytes[bin_at + 8..bin_at + 8 + declared].to_vec(),
    }
}

impl Glb {
    /// The floats of accessor `i` (tightly packed f32).
    fn floats(&self, i: usize) -> Vec<f32> {
        let acc = &self.root.accessors[i];
        assert!(matches!(
            acc.component_type,
            Valid(gltf_json::accessor::GenericComponentType(
                ComponentType::F32
            ))
        ));
        let width = match acc.type_ {
            Valid(Type::Scalar) => 1,
            Valid(Type::Vec3) => 3,
            _ => panic!("unexpected accessor type"),
        };
        let view = &self.root.buffer_views[acc.buffer_view.unwrap().value()];
        assert!(view.byte_stride.is_none());
        let start = view.byte_offset.map_or(0, |o| o.0) as usize
            + acc.byte_offset.map_or(0, |o| o.0) as usize;
        let n = acc.count.0 as usize * width;
        assert!(
            start + 4 * n
                <= view.byte_offset.map_or(0, |o| o.0) as usize + view.byte_length.0 as usize
        );
        (0..n)
            .map(|k| {
                f32::from_le_bytes(
                    self.bin[start + 4 * k..start + 4 * k + 4]
                        .try_into()
                        .unwrap(),
                )
            })
            .collect()
    }

    fn node_index(&self, name: &str) -> usize {
        self.root
            .nodes
            .iter()
            .position(|n| n.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no node {name}"))
    }

    /// World positions of every node at each frame: the sum of animated translations from
    /// the scene root down.
    fn forward_kinematics(&self) -> Vec<Vec<[f32; 3]>> {
        let n = self.root.nodes.len();
        let anim = &self.root.animations[0];
        let mut local: Vec<Vec<f32>> = vec![Vec::new(); n];
        for ch in &anim.channels {
            assert_eq!(ch.target.path, Valid(Property::Translation));
            let s = &anim.samplers[ch.sampler.value()];
            assert_eq!(s.interpolation, Valid(Interpolation::Linear));
            local[ch.target.node.value()] = self.floats(s.output.value());
        }
        let frames = local[0].len() / 3;
        let mut parent = vec![None; n];
        for (i, node) in self.root.nodes.iter().enumerate() {
            for c in node.children.iter().flatten() {
                assert!(parent[c.value()].is_none(), "node with two parents");
                parent[c.value()] = Some(i);
            }
        }
        (0..frames)
            .map(|f| {
                (0..n)
                    .map(|mut i| {
                        let mut p = [0.0f32; 3];
                        loop {
                            for c in 0..3 {
                                p[c] += local[i][3 * f + c];
                            }
                            match parent[i] {
                                Some(up) => i = up,
                                None => break p,
                            }
                        }
                    })
                    .collect()
            })
            .collect()
    }
}

fn write_and_parse(m: &Motion) -> Glb {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.glb");
    assert_eq!(MotionFormat::from_path(&path).unwrap(), MotionFormat::Glb);
    m.write(&path, MotionFormat::Glb).unwrap();
    // Nothing but the file is left in the folder (atomic write).
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    parse(&std::fs::read(&path).unwrap())
}

#[test]
fn glb_holds_the_hierarchy_and_fk_reproduces_the_motion() {
    let m = motion(true);
    let glb = write_and_parse(&m);
    let root = &glb.root;
    assert_eq!(root.nodes.len(), MOTION_NODES.len());
    assert_eq!(root.nodes.len(), 16);
    assert_eq!(root.asset.version, "2.0");
    // Hierarchy: root → hips → neck → r_shoulder → r_elbow → r_wrist → bow → bow_tip.
    let chain = [
        "root",
        "hips",
        "neck",
        "r_shoulder",
        "r_elbow",
        "r_wrist",
        "bow",
        "bow_tip",
    ];
    for w in chain.windows(2) {
        let (up, down) = (glb.node_index(w[0]), glb.node_index(w[1]));
        let kids = root.nodes[up].children.clone().unwrap_or_default();
        assert!(
            kids.iter().any(|k| k.value() == down),
            "{} under {}",
            w[1],
            w[0]
        );
    }
    let scene = &root.scenes[root.scene.unwrap().value()];
    assert_eq!(scene.nodes.len(), 1);
    assert_eq!(scene.nodes[0].value(), glb.node_index("root"));

    // One animation, one LINEAR translation channel per node, FRAMES samples each.
    assert_eq!(root.animations.len(), 1);
    let anim = &root.animations[0];
    assert_eq!(anim.channels.len(), 16);
    let input = anim.samplers[0].input.value();
    let times = glb.floats(input);
    assert_eq!(times.len(), FRAMES);
    assert_eq!(times[0], 0.0);
    assert!((times[FRAMES - 1] - (FRAMES - 1) as f32 / 30.0).abs() < 1e-6);
    let acc = &root.accessors[input];
    assert_eq!(acc.min.as_ref().unwrap()[0].as_f64().unwrap(), 0.0);
    assert_eq!(
        acc.max.as_ref().unwrap()[0].as_f64().unwrap() as f32,
        times[FRAMES - 1]
    );
    for s in &anim.samplers {
        assert_eq!(s.input.value(), input);
        assert_eq!(root.accessors[s.output.value()].count.0 as usize, FRAMES);
    }

    // Forward kinematics of the translations gives back every joint and instrument point.
    let fk = glb.forward_kinematics();
    let joints = m.frames_3d().unwrap();
    let inst = m.instrument_3d().unwrap();
    let joint = |j: Joint| joints.index_axis(Axis(1), j.index()).to_owned();
    let point = |p: InstrumentPoint| inst.index_axis(Axis(1), p as usize).to_owned();
    let targets: Vec<(&str, Array2<f32>)> = vec![
        ("head", joint(Joint::Nose)),
        ("r_wrist", joint(Joint::RWrist)),
        ("l_wrist", joint(Joint::LWrist)),
        ("l_hip", joint(Joint::LHip)),
        ("hips", (joint(Joint::RHip) + joint(Joint::LHip)) * 0.5),
        ("bow_tip", point(InstrumentPoint::BowTip)),
        ("violin_scroll", point(InstrumentPoint::ViolinScroll)),
    ];
    let mut worst = 0.0f32;
    for (name, want) in &targets {
        let i = glb.node_index(name);
        for (f, frame) in fk.iter().enumerate() {
            for (c, v) in frame[i].iter().enumerate() {
                worst = worst.max((v - want[[f, c]]).abs());
            }
        }
    }
    assert!(worst < 1e-5, "FK differs from the motion by {worst} m");
    // Rest pose = first frame.
    let r_wrist = glb.node_index("r_wrist");
    let t0 = root.nodes[r_wrist].translation.unwrap();
    let elbow = Joint::RElbow.index();
    for c in 0..3 {
        let want = joints[[0, Joint::RWrist.index(), c]] - joints[[0, elbow, c]];
        assert!((t0[c] - want).abs() < 1e-6);
    }
}

#[test]
fn without_instrument_points_the_instrument_nodes_are_left_out() {
    let glb = write_and_parse(&motion(false));
    assert_eq!(glb.root.nodes.len(), 12);
    // ("r_elbow" contains "bow": compare whole names.)
    let names: Vec<_> = glb
        .root
        .nodes
        .iter()
        .map(|n| n.name.clone().unwrap())
        .collect();
    for gone in ["bow", "bow_tip", "violin", "violin_scroll"] {
        assert!(!names.iter().any(|n| n == gone), "{names:?}");
    }
    assert_eq!(glb.root.animations[0].channels.len(), 12);
}

#[test]
fn a_2d_only_motion_is_a_clear_error_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.glb");
    let m = Motion::new(30.0, Array3::zeros((5, 10, 2))).unwrap();
    let err = m.write(&path, MotionFormat::Glb).unwrap_err();
    assert!(matches!(err, SkeletonError::MissingTrack { .. }), "{err}");
    assert!(err.to_string().contains("3-D"), "{err}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    let read = Motion::read(&path, MotionFormat::Glb).unwrap_err();
    assert!(read.to_string().contains("not supported"), "{read}");
}

#[test]
fn a_non_finite_coordinate_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let mut joints = Array3::<f32>::zeros((3, 10, 3));
    joints[[2, Joint::LElbow.index(), 1]] = f32::INFINITY;
    let m = Motion::new(30.0, Array3::zeros((3, 10, 2)))
        .unwrap()
        .with_3d(joints)
        .unwrap();
    let err = m
        .write(dir.path().join("m.glb"), MotionFormat::Glb)
        .unwrap_err();
    assert!(err.to_string().contains("l_elbow"), "{err}");
}
