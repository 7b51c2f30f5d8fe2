//! Reading an OpenPose output directory: files ordered by the frame number in their names,
//! layout detected from the keypoint count, our ten joints of every person kept.

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use skeleton::formats::{openpose_frame_number, OpenPoseFrame};
use skeleton::{Joint, PoseLayout, JOINT_COUNT};

use crate::error::{PosePreprocError, Result};

/// One detected person: `[x, y, confidence]` of each of our joints in [`Joint::ALL`] order.
/// A negative or non-finite coordinate or confidence is stored with confidence 0 (missing).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Detection {
    /// `[x, y, confidence]` per joint.
    pub joints: [[f32; 3]; JOINT_COUNT],
}

/// The people of every frame of a directory, in frame order.
#[derive(Debug, Clone, PartialEq)]
pub struct RawPoses {
    /// Body model of the files.
    pub layout: PoseLayout,
    /// `frames[t]`: the people of frame `t` (frame numbers counted from the first file's).
    /// A frame whose file is missing from the numbering is empty.
    pub frames: Vec<Vec<Detection>>,
    /// Number of keypoint files read.
    pub source_files: usize,
    /// Frame numbers between the first and last file that have no file.
    pub missing_frame_files: usize,
    /// Entries of the directory that were skipped, each with the reason (files that are not
    /// `.json`, other JSON files beside `*_keypoints.json`).
    pub skipped: Vec<String>,
    /// Keypoints dropped as missing because a coordinate was negative or not a number
    /// (`NaN`/`Infinity`, as Python's json module writes them), and the first file with one.
    pub bad_keypoints: usize,
    /// The first file with a bad keypoint.
    pub first_bad_keypoint_file: Option<PathBuf>,
}

/// A parsed file: its layout (if it has any person), people, and keypoints dropped.
struct ParsedFile {
    layout: Option<PoseLayout>,
    people: Vec<Detection>,
    bad_keypoints: usize,
}

/// The listing of a directory: frame files by number and the entries skipped.
struct Listing {
    files: Vec<(u64, PathBuf)>,
    skipped: Vec<String>,
}

fn io_error(path: &Path, source: std::io::Error) -> PosePreprocError {
    PosePreprocError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The JSON files of `dir` with their frame numbers, ordered by number. `*_keypoints.json`
/// files are used when there are any (other JSON files are then ignored), else every `.json`.
fn list_frame_files(dir: &Path) -> Result<Listing> {
    if !dir.exists() {
        return Err(PosePreprocError::NotFound {
            dir: dir.to_path_buf(),
        });
    }
    if !dir.is_dir() {
        return Err(PosePreprocError::NotADirectory {
            path: dir.to_path_buf(),
        });
    }
    let mut entries = 0usize;
    let mut json = Vec::new();
    let mut skipped = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| io_error(dir, e))? {
        let entry = entry.map_err(|e| io_error(dir, e))?;
        entries += 1;
        let name = entry.file_name().to_string_lossy().into_owned();
        if !name.to_ascii_lowercase().ends_with(".json") {
            if !name.starts_with('.') {
                skipped.push(format!("{name} (not a .json file)"));
            }
            continue;
        }
        let path = entry.path();
        // The entry's type needs no extra system call; a symbolic link is followed.
        let is_file = match entry.file_type() {
            Ok(t) if t.is_symlink() => path.is_file(),
            Ok(t) => t.is_file(),
            Err(_) => path.is_file(),
        };
        if is_file {
            json.push((name, path));
        }
    }
    if entries == 0 {
        return Err(PosePreprocError::EmptyDirectory {
            dir: dir.to_path_buf(),
        });
    }
    if json.is_empty() {
        return Err(PosePreprocError::NoJsonFiles {
            dir: dir.to_path_buf(),
            entries,
        });
    }
    if json.iter().any(|(n, _)| n.ends_with("_keypoints.json")) {
        for (n, _) in json.iter().filter(|(n, _)| !n.ends_with("_keypoints.json")) {
            skipped.push(format!("{n} (not *_keypoints.json)"));
        }
        json.retain(|(n, _)| n.ends_with("_keypoints.json"));
    }
    skipped.sort();
    let mut files = Vec::with_capacity(json.len());
    for (name, path) in json {
        let lower = name.to_ascii_lowercase();
        let number = openpose_frame_number(&lower)
            .ok_or_else(|| PosePreprocError::NoFrameNumber { file: path.clone() })?;
        files.push((number, path));
    }
    files.sort();
    if let Some(w) = files.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(PosePreprocError::DuplicateFrame {
            file: w[1].1.clone(),
            other: w[0].1.clone(),
            frame: w[0].0,
        });
    }
    Ok(Listing { files, skipped })
}

/// `bytes` with the bare tokens `NaN`, `Infinity` and `-Infinity` (outside strings) replaced
/// by `-1`, so that a file written by Python's json module parses; the keypoint then has a
/// negative value and is dropped as missing. `None` when there is no such token.
fn replace_non_finite_tokens(bytes: &[u8]) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(bytes.len());
    let (mut in_string, mut escaped, mut changed) = (false, false, false);
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if in_string {
            out.push(b);
            match (escaped, b) {
                (true, _) => escaped = false,
                (false, b'\\') => escaped = true,
                (false, b'"') => in_string = false,
                _ => {}
            }
            i += 1;
            continue;
        }
        if b == b'"' {
            in_string = true;
        }
        let rest = &bytes[i..];
        let token = [&b"-Infinity"[..], b"Infinity", b"NaN"]
            .into_iter()
            .find(|t| rest.starts_with(t));
        if let Some(t) = token {
            out.extend_from_slice(b"-1");
            i += t.len();
            changed = true;
        } else {
            out.push(b);
            i += 1;
        }
    }
    changed.then_some(out)
}

/// Parses one keypoints file, keeping our joints of each person.
fn parse_file(path: &Path) -> Result<ParsedFile> {
    let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
    let frame: OpenPoseFrame = match serde_json::from_slice(&bytes) {
        Ok(frame) => frame,
        Err(e) => replace_non_finite_tokens(&bytes)
            .and_then(|fixed| serde_json::from_slice(&fixed).ok())
            .ok_or_else(|| PosePreprocError::MalformedJson {
                file: path.to_path_buf(),
                message: e.to_string(),
            })?,
    };
    let mut bad_keypoints = 0;
    let mut layout = None;
    let mut people = Vec::with_capacity(frame.people.len());
    for (index, person) in frame.people.iter().enumerate() {
        let (values, stride) = person.body_values();
        if values.is_empty() {
            continue; // a person without body keypoints (face or hands only)
        }
        let keypoints = values.len() / stride;
        let this = PoseLayout::from_keypoint_count(keypoints)
            .filter(|_| values.len() % stride == 0)
            .ok_or(PosePreprocError::WrongKeypointCount {
                file: path.to_path_buf(),
                person: index,
                values: values.len(),
                stride,
                keypoints,
            })?;
        match layout {
            None => layout = Some(this),
            Some(first) if first != this => {
                return Err(PosePreprocError::MixedLayouts {
                    dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
                    first_file: path.to_path_buf(),
                    first,
                    other_file: path.to_path_buf(),
                    other: this,
                });
            }
            Some(_) => {}
        }
        let mut joints = [[0.0f32; 3]; JOINT_COUNT];
        for j in Joint::ALL {
            let k = j.openpose_index(this) * stride;
            let (x, y, c) = (values[k], values[k + 1], values[k + stride - 1]);
            let finite = x.is_finite() && y.is_finite() && c.is_finite();
            let ok = finite && x >= 0.0 && y >= 0.0 && c >= 0.0;
            if !ok {
                bad_keypoints += 1;
            }
            joints[j.index()] = if ok { [x, y, c] } else { [0.0, 0.0, 0.0] };
        }
        people.push(Detection { joints });
    }
    Ok(ParsedFile {
        layout,
        people,
        bad_keypoints,
    })
}

/// Reads every frame of an OpenPose output directory.
///
/// Files are ordered by the number in their names (`NAME_000000000042_keypoints.json` is
/// frame 42), not by directory order; numbering holes become frames without people. The
/// layout (COCO-18 or BODY_25) is detected from each person's keypoint count and must be the
/// same in every file. `pose_keypoints_2d` is used (3 values per keypoint); when a person has
/// only `pose_keypoints_3d` (4 values), its z is dropped. Unknown fields are ignored and
/// missing optional ones tolerated. Entries that are not frame files are skipped and listed
/// in [`RawPoses::skipped`]; keypoints with a negative coordinate or a `NaN`/`Infinity`
/// (which Python's json module writes) are dropped as missing and counted. Files are parsed
/// in parallel.
pub fn read_openpose_dir(dir: &Path) -> Result<RawPoses> {
    let Listing { files, skipped } = list_frame_files(dir)?;
    let parsed: Vec<Result<ParsedFile>> = files.par_iter().map(|(_, p)| parse_file(p)).collect();
    let first_number = files.first().map_or(0, |f| f.0);
    let last_number = files.last().map_or(0, |f| f.0);
    let frame_count = usize::try_from(last_number - first_number + 1).unwrap_or(usize::MAX);
    if frame_count > 10 * files.len() + 1000 {
        return Err(PosePreprocError::SparseNumbering {
            dir: dir.to_path_buf(),
            first: first_number,
            last: last_number,
            files: files.len(),
        });
    }
    let mut frames = vec![Vec::new(); frame_count];
    let mut layout: Option<(PoseLayout, &Path)> = None;
    let mut bad_keypoints = 0;
    let mut first_bad_keypoint_file = None;
    for ((number, path), result) in files.iter().zip(parsed) {
        let file = result?;
        if file.bad_keypoints > 0 {
            bad_keypoints += file.bad_keypoints;
            first_bad_keypoint_file.get_or_insert_with(|| path.clone());
        }
        if let Some(this) = file.layout {
            match layout {
                None => layout = Some((this, path)),
                Some((first, first_file)) if first != this => {
                    return Err(PosePreprocError::MixedLayouts {
                        dir: dir.to_path_buf(),
                        first_file: first_file.to_path_buf(),
                        first,
                        other_file: path.clone(),
                        other: this,
                    });
                }
                Some(_) => {}
            }
        }
        let index = usize::try_from(number - first_number).unwrap_or(usize::MAX);
        if let Some(slot) = frames.get_mut(index) {
            *slot = file.people;
        }
    }
    let Some((layout, _)) = layout else {
        return Err(PosePreprocError::NoPerson {
            dir: dir.to_path_buf(),
            frames: frame_count,
        });
    };
    Ok(RawPoses {
        layout,
        frames,
        source_files: files.len(),
        missing_frame_files: frame_count - files.len(),
        skipped,
        bad_keypoints,
        first_bad_keypoint_file,
    })
}
