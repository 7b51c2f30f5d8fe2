//! OpenPose directories: one `{prefix}_{frame:012}_keypoints.json` per frame, in OpenPose's
//! own schema, BODY_25 or COCO-18 order. A motion with a performer track writes its whole
//! body (all 25 points) and both 21-point hands; without one, the ten core joints (BODY_25's
//! MidHip as the mean of the hips) and hands of 21 points with confidence 0.

use std::io::Write;
use std::path::{Path, PathBuf};

use ndarray::Array3;
use serde::{Deserialize, Serialize};

use super::check::format_error;
use crate::body25::BodyPoint;
use crate::error::{Result, SkeletonError};
use crate::hand::HAND_POINT_COUNT;
use crate::joint::{Joint, PoseLayout, JOINT_COUNT};
use crate::motion::Motion;
use crate::performer::PerformerPart;

/// How to write an OpenPose directory.
///
/// ```
/// let o = skeleton::OpenPoseOptions::default();
/// assert_eq!(o.layout, skeleton::PoseLayout::Body25);
/// assert_eq!(o.name_prefix, "motion");
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct OpenPoseOptions {
    /// Keypoint order: BODY_25 (OpenPose's default) or COCO-18.
    pub layout: PoseLayout,
    /// File names are `{name_prefix}_{frame:012}_keypoints.json`.
    pub name_prefix: String,
}

impl Default for OpenPoseOptions {
    fn default() -> Self {
        Self {
            layout: PoseLayout::Body25,
            name_prefix: "motion".into(),
        }
    }
}

impl OpenPoseOptions {
    /// BODY_25 frames named after the folder they go in (`take1_pose/` →
    /// `take1_pose_000000000000_keypoints.json`), as OpenPose names a video's frames.
    ///
    /// ```
    /// let o = skeleton::formats::OpenPoseOptions::named_after(std::path::Path::new("out/take1"));
    /// assert_eq!(o.name_prefix, "take1");
    /// ```
    pub fn named_after(dir: &std::path::Path) -> Self {
        Self {
            layout: PoseLayout::Body25,
            name_prefix: dir
                .file_name()
                .map_or_else(|| "motion".into(), |n| n.to_string_lossy().to_string()),
        }
    }
}

/// The file name OpenPose gives frame `frame` of a video called `prefix`.
///
/// ```
/// assert_eq!(skeleton::formats::openpose_file_name("take1", 7), "take1_000000000007_keypoints.json");
/// ```
pub fn openpose_file_name(prefix: &str, frame: usize) -> String {
    format!("{prefix}_{frame:012}_keypoints.json")
}

/// The frame number in an OpenPose file name: the last run of digits before
/// `_keypoints.json` (or before `.json` for other names). `None` when there is none.
///
/// ```
/// use skeleton::formats::openpose_frame_number;
/// assert_eq!(openpose_frame_number("take1_000000000042_keypoints.json"), Some(42));
/// assert_eq!(openpose_frame_number("cam2_frame17.json"), Some(17));
/// assert_eq!(openpose_frame_number("notes.json"), None);
/// ```
pub fn openpose_frame_number(file_name: &str) -> Option<u64> {
    let stem = file_name
        .strip_suffix("_keypoints.json")
        .or_else(|| file_name.strip_suffix(".json"))?;
    let digits_start = stem
        .char_indices()
        .rev()
        .take_while(|(_, c)| c.is_ascii_digit())
        .last()?
        .0;
    stem[digits_start..].parse().ok()
}

/// One OpenPose frame file as read: only the fields the product uses; any other field is
/// ignored, absent optional fields default to empty.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
pub struct OpenPoseFrame {
    /// The people detected in the frame.
    #[serde(default)]
    pub people: Vec<OpenPosePerson>,
}

/// One detected person in an [`OpenPoseFrame`].
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
pub struct OpenPosePerson {
    /// `[x, y, confidence] × keypoints`, pixels.
    #[serde(default)]
    pub pose_keypoints_2d: Vec<f32>,
    /// `[x, y, z, confidence] × keypoints` (multi-camera OpenPose), when present.
    #[serde(default)]
    pub pose_keypoints_3d: Vec<f32>,
}

impl OpenPosePerson {
    /// The body keypoint values and the number of values per keypoint: `pose_keypoints_2d`
    /// with 3 (x, y, c) when it is not empty, else `pose_keypoints_3d` with 4 (x, y, z, c; z
    /// is to be dropped). Keypoint `k` is at `values[k * stride ..]`, its confidence is the
    /// last of its values.
    pub fn body_values(&self) -> (&[f32], usize) {
        if self.pose_keypoints_2d.is_empty() && !self.pose_keypoints_3d.is_empty() {
            (&self.pose_keypoints_3d, 4)
        } else {
            (&self.pose_keypoints_2d, 3)
        }
    }
}

#[derive(Serialize)]
struct PersonOut<'a> {
    person_id: [i32; 1],
    pose_keypoints_2d: &'a [f32],
    face_keypoints_2d: [f32; 0],
    hand_left_keypoints_2d: &'a [f32],
    hand_right_keypoints_2d: &'a [f32],
    pose_keypoints_3d: [f32; 0],
    face_keypoints_3d: [f32; 0],
    hand_left_keypoints_3d: [f32; 0],
    hand_right_keypoints_3d: [f32; 0],
}

#[derive(Serialize)]
struct FrameOut<'a> {
    version: f32,
    people: [PersonOut<'a>; 1],
}

/// BODY_25's MidHip keypoint, which pose-conditioned generators draw: not one of ours, written
/// as the mean of the two hips.
const BODY25_MID_HIP: usize = 8;

/// Reused per-frame buffers: body keypoints and the two hands.
#[derive(Default)]
struct Buffers {
    body: Vec<f32>,
    left: Vec<f32>,
    right: Vec<f32>,
}

/// Fills `out` (x, y, c per point) from frame `t` of a `(T, points, 2)` track, or with
/// `points` zero triples when there is no track.
fn fill_hand(track: Option<&ndarray::Array3<f32>>, t: usize, out: &mut Vec<f32>) {
    out.clear();
    match track {
        Some(a) => {
            for p in a.index_axis(ndarray::Axis(0), t).rows() {
                out.extend([p[0], p[1], 1.0]);
            }
        }
        None => out.resize(3 * HAND_POINT_COUNT, 0.0),
    }
}

/// Fills the buffers from frame `t` of `motion`: the performer's body points (all of BODY_25,
/// or those COCO-18 has) and hands when the motion has a performer, else our joints with
/// BODY_25's MidHip as the mean of the hips; confidence 1 for every written point, everything
/// else (and absent hands) 0, 0, 0.
fn frame_keypoints(motion: &Motion, t: usize, layout: PoseLayout, b: &mut Buffers) {
    let keypoints = &mut b.body;
    keypoints.clear();
    keypoints.resize(3 * layout.keypoint_count(), 0.0);
    let performer = motion.performer();
    if let Some(p) = performer {
        let body = p.track(PerformerPart::Body).index_axis(ndarray::Axis(0), t);
        for point in BodyPoint::ALL {
            let k = match layout {
                PoseLayout::Body25 => Some(point.index()),
                PoseLayout::Coco18 => point.coco18_index(),
            };
            if let Some(k) = k {
                keypoints[3 * k] = body[[point.index(), 0]];
                keypoints[3 * k + 1] = body[[point.index(), 1]];
                keypoints[3 * k + 2] = 1.0;
            }
        }
    }
    let frame = motion.frames().index_axis(ndarray::Axis(0), t);
    for j in Joint::ALL {
        let k = j.openpose_index(layout);
        keypoints[3 * k] = frame[[j.index(), 0]];
        keypoints[3 * k + 1] = frame[[j.index(), 1]];
        keypoints[3 * k + 2] = 1.0;
    }
    if layout == PoseLayout::Body25 && performer.is_none() {
        let (r, l) = (Joint::RHip.index(), Joint::LHip.index());
        keypoints[3 * BODY25_MID_HIP] = 0.5 * (frame[[r, 0]] + frame[[l, 0]]);
        keypoints[3 * BODY25_MID_HIP + 1] = 0.5 * (frame[[r, 1]] + frame[[l, 1]]);
        keypoints[3 * BODY25_MID_HIP + 2] = 1.0;
    }
    fill_hand(
        performer.map(|p| p.track(PerformerPart::LeftHand)),
        t,
        &mut b.left,
    );
    fill_hand(
        performer.map(|p| p.track(PerformerPart::RightHand)),
        t,
        &mut b.right,
    );
}

/// Writes frame `frame` of `motion` as one OpenPose keypoints JSON document to `writer`.
///
/// ```
/// use ndarray::Array3;
/// use skeleton::{formats::write_openpose_frame, Motion, OpenPoseOptions};
/// let m = Motion::new(30.0, Array3::from_elem((1, 10, 2), 5.0))?;
/// let mut bytes = Vec::new();
/// write_openpose_frame(&m, 0, &OpenPoseOptions::default(), &mut bytes)?;
/// let text = String::from_utf8(bytes).unwrap();
/// assert!(text.starts_with(r#"{"version":1.3,"people":[{"person_id":[-1],"pose_keypoints_2d":[5.0,5.0,1.0"#));
/// # Ok::<(), skeleton::SkeletonError>(())
/// ```
pub fn write_openpose_frame(
    motion: &Motion,
    frame: usize,
    options: &OpenPoseOptions,
    writer: impl Write,
) -> Result<()> {
    let path = super::check::memory_path();
    if frame >= motion.len() {
        return Err(SkeletonError::Format {
            path,
            reason: format!("frame {frame} is past the motion's {} frames", motion.len()),
        });
    }
    super::check::check_writable(motion, &path, false)?;
    let mut buffers = Buffers::default();
    write_frame(motion, frame, options.layout, &mut buffers, writer, &path)
}

fn write_frame(
    motion: &Motion,
    t: usize,
    layout: PoseLayout,
    buffers: &mut Buffers,
    mut writer: impl Write,
    path: &Path,
) -> Result<()> {
    frame_keypoints(motion, t, layout, buffers);
    let out = FrameOut {
        version: 1.3,
        people: [PersonOut {
            person_id: [-1],
            pose_keypoints_2d: &buffers.body,
            face_keypoints_2d: [],
            hand_left_keypoints_2d: &buffers.left,
            hand_right_keypoints_2d: &buffers.right,
            pose_keypoints_3d: [],
            face_keypoints_3d: [],
            hand_left_keypoints_3d: [],
            hand_right_keypoints_3d: [],
        }],
    };
    serde_json::to_writer(&mut writer, &out).map_err(|e| SkeletonError::Io {
        path: path.to_path_buf(),
        source: e.into(),
    })
}

/// Writes the whole directory atomically (see [`Motion::write_openpose`]).
pub(crate) fn write_dir(motion: &Motion, dir: &Path, options: &OpenPoseOptions) -> Result<()> {
    if options.name_prefix.contains(['/', '\\']) {
        return Err(SkeletonError::Format {
            path: dir.to_path_buf(),
            reason: format!(
                "OpenPose name prefix {:?} must not contain a path separator",
                options.name_prefix
            ),
        });
    }
    super::files::write_dir(dir, |tmp| {
        let mut buffers = Buffers::default();
        let mut buffer = Vec::with_capacity(4096);
        for t in 0..motion.len() {
            let file = tmp.join(openpose_file_name(&options.name_prefix, t));
            buffer.clear();
            write_frame(motion, t, options.layout, &mut buffers, &mut buffer, &file)?;
            std::fs::write(&file, &buffer).map_err(|e| SkeletonError::Io {
                path: dir.join(openpose_file_name(&options.name_prefix, t)),
                source: e,
            })?;
        }
        Ok(())
    })
}

/// The `*_keypoints.json` files of `dir`, ordered by frame number.
fn keypoint_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir).map_err(|e| SkeletonError::Io {
        path: dir.to_path_buf(),
        source: e,
    })?;
    let mut files = Vec::new();
    for entry in entries {
        let path = entry
            .map_err(|e| SkeletonError::Io {
                path: dir.to_path_buf(),
                source: e,
            })?
            .path();
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
        let Some(name) = name.filter(|n| n.ends_with("_keypoints.json")) else {
            continue;
        };
        let Some(number) = openpose_frame_number(&name) else {
            return Err(format_error(&path, "no frame number in the file name"));
        };
        files.push((number, path));
    }
    files.sort();
    if let Some(w) = files.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(format_error(
            &w[1].1,
            format!(
                "same frame number as {}; one video per directory",
                w[0].1.display()
            ),
        ));
    }
    Ok(files.into_iter().map(|(_, p)| p).collect())
}

/// Reads a clean single-person OpenPose directory (see [`Motion::read_openpose`]).
pub(crate) fn read_dir(dir: &Path, fps: f64) -> Result<Motion> {
    if !dir.is_dir() {
        return Err(format_error(
            dir,
            "not a directory; an OpenPose motion is a directory of *_keypoints.json files",
        ));
    }
    let files = keypoint_files(dir)?;
    if files.is_empty() {
        return Err(SkeletonError::Empty {
            path: dir.to_path_buf(),
        });
    }
    let mut frames = Array3::<f32>::zeros((files.len(), JOINT_COUNT, 2));
    let mut layout: Option<PoseLayout> = None;
    for (t, file) in files.iter().enumerate() {
        let bytes = super::files::read_file(file)?;
        let parsed: OpenPoseFrame = serde_json::from_slice(&bytes)
            .map_err(|e| format_error(file, format!("not OpenPose JSON: {e}")))?;
        let [person] = parsed.people.as_slice() else {
            return Err(format_error(
                file,
                format!(
                    "holds {} people; a plain read needs exactly one: read raw OpenPose output with pose-preproc (`violin-skeleton pose-labels`)",
                    parsed.people.len()
                ),
            ));
        };
        let (values, stride) = person.body_values();
        let count = values.len() / stride;
        let this_layout = PoseLayout::from_keypoint_count(count)
            .filter(|_| values.len() % stride == 0)
            .ok_or_else(|| SkeletonError::FileShape {
                path: file.clone(),
                what: format!(
                    "{} keypoint values; expected 18 (COCO-18) or 25 (BODY_25) keypoints × {stride}",
                    values.len()
                ),
            })?;
        if *layout.get_or_insert(this_layout) != this_layout {
            return Err(format_error(
                file,
                format!("{this_layout:?} keypoints, earlier files are {layout:?}; one layout per directory"),
            ));
        }
        for j in Joint::ALL {
            let k = j.openpose_index(this_layout) * stride;
            let (x, y, c) = (values[k], values[k + 1], values[k + stride - 1]);
            if !(c > 0.0 && x.is_finite() && y.is_finite()) {
                return Err(format_error(
                    file,
                    format!("joint {} is not detected (confidence {c}); read raw OpenPose output with pose-preproc, which fills gaps", j.name()),
                ));
            }
            frames[[t, j.index(), 0]] = x;
            frames[[t, j.index(), 1]] = y;
        }
    }
    if !(fps.is_finite() && fps > 0.0) {
        return Err(SkeletonError::InvalidFps(fps));
    }
    Motion::new(fps, frames)
}
