//! The product's motion JSON (ARCHITECTURE.md, "File schemas").

use std::io::{Read, Write};
use std::path::Path;

use serde::ser::Serializer;
use serde::{Deserialize, Serialize};

use super::check::format_error;
use super::track_json::{column_order, to_track, RawTrack, Track};
use crate::error::{Result, SkeletonError};
use crate::joint::{Joint, JOINT_COUNT};
use crate::motion::{InstrumentPoint, Motion};

/// The frame rate as an integer when it is one (`"fps": 30`), else as a float.
fn serialize_fps<S: Serializer>(fps: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    if fps.fract() == 0.0 && *fps <= 1e9 {
        s.serialize_u64(*fps as u64)
    } else {
        s.serialize_f64(*fps)
    }
}

#[derive(Serialize)]
struct MotionJsonOut<'a> {
    #[serde(serialize_with = "serialize_fps")]
    fps: f64,
    joints: [&'static str; JOINT_COUNT],
    frames: Track<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    frames_3d: Option<Track<'a>>,
    units: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    image_size: Option<[u32; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    instrument_points: Option<[&'static str; 4]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    instrument: Option<Track<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    instrument_3d: Option<Track<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    performer: Option<super::performer_json::PerformerOut<'a>>,
}

/// Writes `motion` as motion JSON to `writer` (all tracks it has).
///
/// ```
/// use ndarray::Array3;
/// let m = skeleton::Motion::new(30.0, Array3::zeros((2, 10, 2)))?;
/// let mut bytes = Vec::new();
/// skeleton::formats::write_json(&m, &mut bytes)?;
/// assert!(String::from_utf8_lossy(&bytes).starts_with(r#"{"fps":30,"joints":["nose""#));
/// assert_eq!(skeleton::formats::read_json_from(bytes.as_slice())?, m);
/// # Ok::<(), skeleton::SkeletonError>(())
/// ```
pub fn write_json(motion: &Motion, writer: impl Write) -> Result<()> {
    let path = super::check::memory_path();
    super::check::check_writable(motion, &path, true)?;
    write(motion, writer, &path)
}

pub(crate) fn write(motion: &Motion, mut writer: impl Write, path: &Path) -> Result<()> {
    let has_instrument = motion.instrument().is_some() || motion.instrument_3d().is_some();
    let out = MotionJsonOut {
        fps: motion.fps(),
        joints: Joint::ALL.map(Joint::name),
        frames: Track(motion.frames()),
        frames_3d: motion.frames_3d().map(Track),
        units: "px",
        image_size: motion.image_size().map(|(w, h)| [w, h]),
        instrument_points: has_instrument.then(|| InstrumentPoint::ALL.map(InstrumentPoint::name)),
        instrument: motion.instrument().map(Track),
        instrument_3d: motion.instrument_3d().map(Track),
        performer: motion
            .performer()
            .map(super::performer_json::PerformerOut::new),
    };
    let io = |e: std::io::Error| SkeletonError::Io {
        path: path.to_path_buf(),
        source: e,
    };
    serde_json::to_writer(&mut writer, &out).map_err(|e| io(e.into()))?;
    writer.write_all(b"\n").map_err(io)
}

#[derive(Deserialize)]
struct MotionJsonIn {
    fps: Option<f64>,
    joints: Option<Vec<String>>,
    frames: Option<RawTrack>,
    frames_3d: Option<RawTrack>,
    units: Option<String>,
    image_size: Option<[u32; 2]>,
    instrument_points: Option<Vec<String>>,
    instrument: Option<RawTrack>,
    instrument_3d: Option<RawTrack>,
    performer: Option<super::performer_json::PerformerIn>,
}

/// Reads motion JSON from `reader` (joints in any order, by name; unknown or missing joints
/// are errors).
pub fn read_json_from(reader: impl Read) -> Result<Motion> {
    let (bytes, path) = super::check::read_all(reader)?;
    read(&bytes, &path)
}

fn missing(path: &Path, field: &str, hint: &str) -> SkeletonError {
    SkeletonError::MissingField {
        path: path.to_path_buf(),
        field: field.into(),
        hint: hint.into(),
    }
}

pub(crate) fn read(bytes: &[u8], path: &Path) -> Result<Motion> {
    let raw: MotionJsonIn = serde_json::from_slice(bytes)
        .map_err(|e| format_error(path, format!("not valid motion JSON: {e}")))?;
    let fps = raw
        .fps
        .ok_or_else(|| missing(path, "fps", "frames per second, e.g. 30"))?;
    if !(fps.is_finite() && fps > 0.0) {
        return Err(format_error(
            path,
            format!("fps must be a positive number, got {fps}"),
        ));
    }
    if let Some(units) = raw.units.as_deref().filter(|u| *u != "px") {
        return Err(format_error(
            path,
            format!("units {units:?} are not supported; the 2-D track must be in pixels (\"px\")"),
        ));
    }
    let joint_names = Joint::ALL.map(Joint::name);
    let names = raw
        .joints
        .ok_or_else(|| missing(path, "joints", "the 10 joint names, in column order"))?;
    let order = column_order(path, &names, &joint_names)?;
    let frames = raw
        .frames
        .ok_or_else(|| missing(path, "frames", "[[[x, y] × 10] × frames]"))?;
    if frames.is_empty() {
        return Err(SkeletonError::Empty {
            path: path.to_path_buf(),
        });
    }
    let shape_error = |e: SkeletonError| format_error(path, e.to_string());
    let mut motion = Motion::new(
        fps,
        to_track(path, "frames", &frames, &order, &joint_names, 2)?,
    )?;
    let frame_count = frames.len();
    let check_len = |field: &str, track: &RawTrack| {
        if track.len() == frame_count {
            Ok(())
        } else {
            Err(SkeletonError::FileShape {
                path: path.to_path_buf(),
                what: format!(
                    "{field} has {} frames, frames has {frame_count}",
                    track.len()
                ),
            })
        }
    };
    if let Some(f3) = &raw.frames_3d {
        check_len("frames_3d", f3)?;
        let track = to_track(path, "frames_3d", f3, &order, &joint_names, 3)?;
        motion = motion.with_3d(track).map_err(shape_error)?;
    }
    if raw.instrument.is_some() || raw.instrument_3d.is_some() {
        let point_names = InstrumentPoint::ALL.map(InstrumentPoint::name);
        let inst_order = match &raw.instrument_points {
            Some(n) => column_order(path, n, &point_names)?,
            None => (0..point_names.len()).collect(),
        };
        if let Some(i2) = &raw.instrument {
            check_len("instrument", i2)?;
            let track = to_track(path, "instrument", i2, &inst_order, &point_names, 2)?;
            motion = motion.with_instrument(track).map_err(shape_error)?;
        }
        if let Some(i3) = &raw.instrument_3d {
            check_len("instrument_3d", i3)?;
            let track = to_track(path, "instrument_3d", i3, &inst_order, &point_names, 3)?;
            motion = motion.with_instrument_3d(track).map_err(shape_error)?;
        }
    }
    if let Some(p) = raw.performer {
        let track = p.into_track(path, frame_count)?;
        motion = motion.with_performer(track).map_err(shape_error)?;
    }
    if let Some([w, h]) = raw.image_size {
        motion = motion.with_image_size(w, h);
    }
    Ok(motion)
}
