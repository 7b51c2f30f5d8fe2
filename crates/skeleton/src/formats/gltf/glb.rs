//! Writing a [`NodeAnimation`] as glTF 2.0 binary (GLB): the JSON document is built with
//! `gltf-json`, the container (12-byte header, a JSON chunk and a BIN chunk) here.

use std::io::Write;

use gltf_json::accessor::{ComponentType, GenericComponentType, Type};
use gltf_json::animation::{Channel, Interpolation, Property, Sampler, Target};
use gltf_json::validation::{Checked::Valid, USize64};
use gltf_json::{Accessor, Animation, Asset, Buffer, Index, Node, Root, Scene};

use super::animation::NodeAnimation;
use crate::error::{Result, SkeletonError};

/// `glTF` in little-endian: the first four bytes of every GLB.
pub const GLB_MAGIC: u32 = 0x4654_6C67;
/// Chunk type of the JSON chunk (`JSON`).
pub const CHUNK_JSON: u32 = 0x4E4F_534A;
/// Chunk type of the binary chunk (`BIN\0`).
pub const CHUNK_BIN: u32 = 0x004E_4942;

const HEADER_BYTES: usize = 12;
const CHUNK_HEADER_BYTES: usize = 8;
const F32_BYTES: usize = 4;

fn too_large(what: String) -> SkeletonError {
    SkeletonError::InvalidAnimation { reason: what }
}

/// Frame times in seconds as f32, checked to increase strictly (the glTF rule for animation
/// inputs; f32 rounding could break it only for absurdly long or fast motions).
fn frame_times_s(anim: &NodeAnimation) -> Result<Vec<f32>> {
    let times: Vec<f32> = (0..anim.frame_count())
        .map(|f| (f as f64 / anim.fps()) as f32)
        .collect();
    if let Some(i) = times.windows(2).position(|w| w[1] <= w[0]) {
        return Err(too_large(format!(
            "frame times {} and {} round to the same 32-bit float; the motion is too long for its frame rate",
            i,
            i + 1
        )));
    }
    Ok(times)
}

/// The BIN chunk's content: frame times, then each node's local translations (x, y, z per
/// frame), all little-endian f32.
fn binary_data(anim: &NodeAnimation, times: &[f32]) -> Vec<u8> {
    let (t, n) = (anim.frame_count(), anim.nodes().len());
    let mut bin = Vec::with_capacity(F32_BYTES * (t + 3 * t * n));
    for v in times {
        bin.extend_from_slice(&v.to_le_bytes());
    }
    for node in 0..n {
        for frame in 0..t {
            for v in anim.local_translation(frame, node) {
                bin.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    bin
}

fn view(root: &mut Root, offset: usize, length: usize) -> Index<gltf_json::buffer::View> {
    root.push(gltf_json::buffer::View {
        buffer: Index::new(0),
        byte_length: USize64::from(length),
        byte_offset: Some(USize64::from(offset)),
        byte_stride: None,
        name: None,
        target: None,
        extensions: None,
        extras: Default::default(),
    })
}

fn float_accessor(
    view: Index<gltf_json::buffer::View>,
    offset: usize,
    count: usize,
    type_: Type,
) -> Accessor {
    Accessor {
        buffer_view: Some(view),
        byte_offset: Some(USize64::from(offset)),
        count: USize64::from(count),
        component_type: Valid(GenericComponentType(ComponentType::F32)),
        extensions: None,
        extras: Default::default(),
        type_: Valid(type_),
        min: None,
        max: None,
        name: None,
        normalized: false,
        sparse: None,
    }
}

/// The glTF document describing `anim`, whose BIN chunk is `bin_len` bytes long.
fn document(anim: &NodeAnimation, times: &[f32], bin_len: usize, name: &str) -> Root {
    let (t, n) = (anim.frame_count(), anim.nodes().len());
    let mut root = Root {
        asset: Asset {
            copyright: None,
            extensions: None,
            extras: Default::default(),
            generator: Some(format!("violin-skeleton {}", env!("CARGO_PKG_VERSION"))),
            min_version: None,
            version: "2.0".into(),
        },
        ..Default::default()
    };
    root.push(Buffer {
        byte_length: USize64::from(bin_len),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let times_view = view(&mut root, 0, F32_BYTES * t);
    let moves_view = view(&mut root, F32_BYTES * t, 3 * F32_BYTES * t * n);
    let mut time = float_accessor(times_view, 0, t, Type::Scalar);
    time.min = Some(serde_json::json!([times.first().copied().unwrap_or(0.0)]));
    time.max = Some(serde_json::json!([times.last().copied().unwrap_or(0.0)]));
    time.name = Some("time_s".into());
    let time = root.push(time);

    let mut samplers = Vec::with_capacity(n);
    let mut channels = Vec::with_capacity(n);
    for (i, node) in anim.nodes().iter().enumerate() {
        let mut output = float_accessor(moves_view, 3 * F32_BYTES * t * i, t, Type::Vec3);
        output.name = Some(format!("{}_translation_m", node.name));
        let output = root.push(output);
        let children: Vec<Index<Node>> = anim
            .children(i)
            .into_iter()
            .map(|c| Index::new(c as u32))
            .collect();
        let node_index = root.push(Node {
            name: Some(node.name.clone()),
            translation: Some(anim.local_translation(0, i)),
            children: (!children.is_empty()).then_some(children),
            ..Default::default()
        });
        let sampler = Index::push(
            &mut samplers,
            Sampler {
                extensions: None,
                extras: Default::default(),
                input: time,
                interpolation: Valid(Interpolation::Linear),
                output,
            },
        );
        channels.push(Channel {
            sampler,
            target: Target {
                extensions: None,
                extras: Default::default(),
                node: node_index,
                path: Valid(Property::Translation),
            },
            extensions: None,
            extras: Default::default(),
        });
    }
    root.push(Animation {
        extensions: None,
        extras: Default::default(),
        channels,
        name: Some(name.into()),
        samplers,
    });
    let scene = root.push(Scene {
        extensions: None,
        extras: Default::default(),
        name: Some(name.into()),
        nodes: anim
            .roots()
            .into_iter()
            .map(|r| Index::new(r as u32))
            .collect(),
    });
    root.scene = Some(scene);
    root
}

fn pad_to_4(bytes: &mut Vec<u8>, fill: u8) {
    while !bytes.len().is_multiple_of(4) {
        bytes.push(fill);
    }
}

/// `anim` as the bytes of a GLB file; `name` names the scene and the animation.
///
/// Every node gets a translation channel (its world position minus its parent's, LINEAR
/// between frames) and its first frame as rest translation. Fails when the file would pass
/// the format's 4 GiB limit.
pub fn glb_bytes(anim: &NodeAnimation, name: &str) -> Result<Vec<u8>> {
    let (t, n) = (anim.frame_count(), anim.nodes().len());
    let bin_len = t
        .checked_mul(n)
        .and_then(|tn| tn.checked_mul(3))
        .and_then(|v| v.checked_add(t))
        .and_then(|v| v.checked_mul(F32_BYTES))
        .filter(|&b| b < u32::MAX as usize)
        .ok_or_else(|| {
            too_large(format!(
                "{t} frames × {n} nodes do not fit in one GLB (4 GiB); write a shorter motion"
            ))
        })?;
    let times = frame_times_s(anim)?;
    let mut bin = binary_data(anim, &times);
    debug_assert_eq!(bin.len(), bin_len);
    let root = document(anim, &times, bin.len(), name);
    let mut json = serde_json::to_vec(&root).map_err(|e| too_large(e.to_string()))?;
    pad_to_4(&mut json, b' ');
    pad_to_4(&mut bin, 0);
    let total = HEADER_BYTES + 2 * CHUNK_HEADER_BYTES + json.len() + bin.len();
    let total_u32 = u32::try_from(total)
        .map_err(|_| too_large(format!("{total} bytes is over the GLB limit of 4 GiB")))?;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(&GLB_MAGIC.to_le_bytes());
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total_u32.to_le_bytes());
    for (kind, chunk) in [(CHUNK_JSON, &json), (CHUNK_BIN, &bin)] {
        // Both chunks are shorter than `total`, which fits in u32.
        out.extend_from_slice(&(chunk.len() as u32).to_le_bytes());
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(chunk);
    }
    Ok(out)
}

/// Writes `anim` as GLB to `out` (see [`glb_bytes`]).
pub fn write_glb(anim: &NodeAnimation, name: &str, mut out: impl Write) -> Result<()> {
    out.write_all(&glb_bytes(anim, name)?)?;
    Ok(())
}
