//! Motion files: JSON, CSV, NPY and OpenPose directories, each read and written, and BVH
//! export of the 3-D track with a parser that checks it ([`bvh`]).
//!
//! | format | what | read | write |
//! |---|---|---|---|
//! | [`MotionFormat::Json`] | `{"fps", "joints", "frames", ["frames_3d"], "units", ["image_size"], ["instrument_points", "instrument", "instrument_3d"], ["performer"]}` | joints in any order, by name; `performer` optional | all tracks |
//! | [`MotionFormat::Csv`] | header `frame,time_s,nose_x,nose_y,…,l_hip_y`, one row per frame | columns by name; fps from `time_s` | 2-D track |
//! | [`MotionFormat::Npy`] | float32 `(T, 20)`: x, y per joint in [`crate::Joint::ALL`] order | needs an fps ([`Motion::read_npy`]); [`Motion::read`] assumes 30 | 2-D track |
//! | [`MotionFormat::Glb`] | glTF 2.0 binary: a node hierarchy with animated translations ([`gltf`]) | not read | 3-D track and 3-D instrument points |
//! | [`MotionFormat::OpenPose`] | a directory of `{prefix}_{frame:012}_keypoints.json` in OpenPose's schema | a clean single-person directory | 2-D track, BODY_25 or COCO-18 |
//!
//! Every file write is atomic: the data goes to a temporary file in the same directory that
//! is renamed into place at the end (an OpenPose directory is written as a temporary
//! directory, then renamed), so a failure never leaves a half-written output. Every read
//! error names the file and the problem.
//!
//! Raw OpenPose output (several people, low-confidence or missing joints, gaps) is read by the
//! `pose-preproc` crate, which picks the performer and fills gaps; [`Motion::read`] with
//! [`MotionFormat::OpenPose`] only reads a clean directory with one fully-detected person per
//! frame, such as the ones this module writes.
//!
//! ```
//! use ndarray::Array3;
//! use skeleton::{Motion, MotionFormat};
//! let dir = tempfile::tempdir()?;
//! let motion = Motion::new(30.0, Array3::from_elem((4, 10, 2), 100.0))?;
//! for name in ["m.json", "m.csv", "m.npy", "m_openpose"] {
//!     let path = dir.path().join(name);
//!     let format = MotionFormat::from_path(&path)?;
//!     motion.write(&path, format)?;
//!     assert_eq!(Motion::read(&path, format)?, motion);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod bvh;
mod check;
mod csv;
mod files;
pub mod gltf;
mod json;
mod npy;
mod openpose;
mod performer_json;
mod track_json;

use std::path::Path;

use crate::error::{Result, SkeletonError};
use crate::motion::Motion;
use check::check_writable;

pub use check::DEFAULT_FPS;
pub use csv::{read_csv_from, write_csv};
pub use json::{read_json_from, write_json};
pub use npy::{read_npy_from, write_npy};
pub use openpose::{
    openpose_file_name, openpose_frame_number, write_openpose_frame, OpenPoseFrame,
    OpenPoseOptions, OpenPosePerson,
};

/// A motion file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MotionFormat {
    /// The product's motion JSON (all tracks).
    Json,
    /// One row per frame: `frame,time_s,nose_x,nose_y,…,l_hip_y`.
    Csv,
    /// float32 `(T, 20)`.
    Npy,
    /// A directory with one OpenPose `*_keypoints.json` per frame (BODY_25 by default).
    #[serde(rename = "openpose")]
    OpenPose,
    /// glTF 2.0 binary of the 3-D track (write only; see [`gltf`]).
    Glb,
}

impl MotionFormat {
    /// Guesses the format from a path: `.json`, `.csv`, `.npy`, `.glb` (any case); an existing
    /// directory or a path without extension is an OpenPose directory.
    ///
    /// ```
    /// use skeleton::MotionFormat;
    /// use std::path::Path;
    /// assert_eq!(MotionFormat::from_path(Path::new("a/take1.CSV"))?, MotionFormat::Csv);
    /// assert_eq!(MotionFormat::from_path(Path::new("a/take1_pose"))?, MotionFormat::OpenPose);
    /// assert!(MotionFormat::from_path(Path::new("take1.txt")).is_err());
    /// # Ok::<(), skeleton::SkeletonError>(())
    /// ```
    pub fn from_path(path: &Path) -> Result<Self> {
        if path.is_dir() {
            return Ok(MotionFormat::OpenPose);
        }
        let Some(ext) = path.extension() else {
            return Ok(MotionFormat::OpenPose);
        };
        match ext.to_string_lossy().to_ascii_lowercase().as_str() {
            "json" => Ok(MotionFormat::Json),
            "csv" => Ok(MotionFormat::Csv),
            "npy" => Ok(MotionFormat::Npy),
            "glb" => Ok(MotionFormat::Glb),
            _ => Err(SkeletonError::UnknownFormat {
                path: path.to_path_buf(),
            }),
        }
    }
}

impl Motion {
    /// Writes the motion to `path` in `format`, atomically (OpenPose: BODY_25, file prefix
    /// `motion`; see [`Motion::write_openpose`] for other options).
    ///
    /// Fails on an empty motion or a non-finite coordinate, naming the frame and joint, and
    /// for [`MotionFormat::Glb`] on a motion without a 3-D track (before anything is written).
    pub fn write(&self, path: impl AsRef<Path>, format: MotionFormat) -> Result<()> {
        let path = path.as_ref();
        match format {
            MotionFormat::Json => {
                check_writable(self, path, true)?;
                files::write_file(path, |w| json::write(self, w, path))
            }
            MotionFormat::Csv => {
                check_writable(self, path, false)?;
                files::write_file(path, |w| csv::write(self, w, path))
            }
            MotionFormat::Npy => {
                check_writable(self, path, false)?;
                files::write_file(path, |w| npy::write(self, w, path))
            }
            MotionFormat::OpenPose => self.write_openpose(path, &OpenPoseOptions::default()),
            MotionFormat::Glb => {
                check_writable(self, path, true)?;
                let anim = gltf::motion_glb_animation(self)?;
                files::write_file(path, |w| gltf::write_glb(&anim, gltf::MOTION_NAME, w))
            }
        }
    }

    /// Writes an OpenPose directory with `options` (layout, file-name prefix), atomically: the
    /// files are written to a temporary directory beside `dir` that is then renamed to `dir`.
    /// An existing `dir` is replaced only when it holds nothing but `*_keypoints.json` files.
    pub fn write_openpose(&self, dir: impl AsRef<Path>, options: &OpenPoseOptions) -> Result<()> {
        let dir = dir.as_ref();
        check_writable(self, dir, false)?;
        openpose::write_dir(self, dir, options)
    }

    /// Reads a motion from `path` in `format` ([`MotionFormat::Glb`] is write-only). NPY and OpenPose files carry no frame rate:
    /// they are read at [`DEFAULT_FPS`] (use [`Motion::read_npy`] / [`Motion::read_openpose`]
    /// for another rate).
    pub fn read(path: impl AsRef<Path>, format: MotionFormat) -> Result<Motion> {
        let path = path.as_ref();
        match format {
            MotionFormat::Json => json::read(&files::read_file(path)?, path),
            MotionFormat::Csv => csv::read(&files::read_file(path)?, path),
            MotionFormat::Npy => Motion::read_npy(path, DEFAULT_FPS),
            MotionFormat::OpenPose => Motion::read_openpose(path, DEFAULT_FPS),
            MotionFormat::Glb => Err(SkeletonError::Format {
                path: path.to_path_buf(),
                reason: "reading .glb is not supported; read the motion's .json (or .csv, .npy, OpenPose folder) instead".into(),
            }),
        }
    }

    /// Reads a float32 (or float64) `(T, 20)` — or `(T, 10, 2)` — NPY file at `fps`.
    pub fn read_npy(path: impl AsRef<Path>, fps: f64) -> Result<Motion> {
        let path = path.as_ref();
        npy::read(&files::read_file(path)?, fps, path)
    }

    /// Reads a clean OpenPose directory (one person per frame, all ten joints detected, as
    /// [`Motion::write_openpose`] writes) at `fps`. Raw OpenPose output goes through the
    /// `pose-preproc` crate instead.
    pub fn read_openpose(dir: impl AsRef<Path>, fps: f64) -> Result<Motion> {
        openpose::read_dir(dir.as_ref(), fps)
    }
}
