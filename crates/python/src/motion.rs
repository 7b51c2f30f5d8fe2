//! `violin_skeleton.Motion`: the skeleton animation as NumPy arrays, and the motion files the
//! command-line tool writes.

use std::path::{Path, PathBuf};

use numpy::{PyArray3, ToPyArray};
use pyo3::prelude::*;
use violin_skeleton::skeleton::canvas::DEFAULT_CANVAS_MARGIN;
use violin_skeleton::skeleton::formats::OpenPoseOptions;
use violin_skeleton::skeleton::Canvas;
use violin_skeleton::skeleton::Joint;
use violin_skeleton::MotionFormat;

use crate::errors::{PyApiError, Result};
use crate::output::check_file_target;

/// A motion file format, as `generate --format` names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SaveFormat {
    /// Motion JSON (2-D, 3-D and instrument tracks).
    Json,
    /// A folder of OpenPose BODY_25 `*_keypoints.json` files.
    OpenPose,
    /// One row per frame.
    Csv,
    /// float32 (frames, 20).
    Npy,
    /// BVH of the 3-D rig.
    Bvh,
    /// glTF 2.0 binary of the 3-D rig.
    Glb,
}

impl SaveFormat {
    /// The format named `name` (`json`, `openpose`, `csv`, `npy`, `bvh`, `glb`).
    pub fn from_name(name: &str) -> Result<Self> {
        match name.to_ascii_lowercase().as_str() {
            "json" => Ok(SaveFormat::Json),
            "openpose" => Ok(SaveFormat::OpenPose),
            "csv" => Ok(SaveFormat::Csv),
            "npy" => Ok(SaveFormat::Npy),
            "bvh" => Ok(SaveFormat::Bvh),
            "glb" => Ok(SaveFormat::Glb),
            _ => Err(PyApiError::InvalidInput(format!(
                "format={name:?}: expected one of json, openpose, csv, npy, bvh, glb"
            ))),
        }
    }

    /// The format a path names, as the command-line tool tells it: by extension, and a path
    /// without one is an OpenPose folder.
    pub fn from_path(path: &Path) -> Result<Self> {
        match path.extension() {
            None => Ok(SaveFormat::OpenPose),
            Some(ext) => Self::from_name(&ext.to_string_lossy()).map_err(|_| {
                PyApiError::InvalidInput(format!(
                    "{}: cannot tell the format from the extension; use .json, .csv, .npy, \
                     .bvh, .glb, a folder name, or format=…",
                    path.display()
                ))
            }),
        }
    }
}

/// A violinist skeleton animation: ten joints per frame at `fps` frames per second.
#[pyclass(frozen, name = "Motion", module = "violin_skeleton")]
pub struct PyMotion {
    inner: violin_skeleton::Motion,
}

impl PyMotion {
    /// Wraps a motion.
    pub fn new(inner: violin_skeleton::Motion) -> Self {
        Self { inner }
    }
}

/// Writes `motion` to `path` in `format`, as `violin-skeleton generate` does.
fn write_motion(motion: &violin_skeleton::Motion, path: &Path, format: SaveFormat) -> Result<()> {
    if format != SaveFormat::OpenPose {
        check_file_target(path)?;
    }
    match format {
        SaveFormat::Json => motion.write(path, MotionFormat::Json),
        SaveFormat::Csv => motion.write(path, MotionFormat::Csv),
        SaveFormat::Npy => motion.write(path, MotionFormat::Npy),
        SaveFormat::Glb => motion.write(path, MotionFormat::Glb),
        // Fitted to the default 1280×720 canvas, as `generate` writes it.
        SaveFormat::OpenPose => motion
            .fitted_to_canvas(Canvas::default(), DEFAULT_CANVAS_MARGIN)
            .write_openpose(path, &OpenPoseOptions::named_after(path)),
        SaveFormat::Bvh => {
            return violin_skeleton::motion_synth::bvh::write_bvh_file(motion, path)
                .map_err(|e| PyApiError::Pipeline(e.into()));
        }
    }
    .map_err(|e| PyApiError::Pipeline(e.into()))
}

#[pymethods]
impl PyMotion {
    /// Joint positions in image pixels, float32 of shape (frames, joints, 2).
    #[getter]
    fn joints<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f32>> {
        self.inner.frames().to_pyarray(py)
    }

    /// Joint positions of the 3-D rig, float32 of shape (frames, joints, 3), or None for a
    /// motion without one (method="gru").
    #[getter]
    fn joints_3d<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray3<f32>>> {
        self.inner.frames_3d().map(|f| f.to_pyarray(py))
    }

    /// The joints' names, in the order of the arrays' second axis.
    #[getter]
    fn joint_names(&self) -> Vec<&'static str> {
        Joint::ALL.iter().map(|j| j.name()).collect()
    }

    /// Frames per second.
    #[getter]
    fn fps(&self) -> f64 {
        self.inner.fps()
    }

    /// Length in seconds.
    #[getter]
    fn duration_s(&self) -> f64 {
        self.inner.duration_s()
    }

    /// The image size `(width, height)` in pixels the 2-D joints are drawn for, if known.
    #[getter]
    fn image_size(&self) -> Option<(u32, u32)> {
        self.inner.image_size()
    }

    /// Writes the motion, atomically, in `format` (`json`, `openpose`, `csv`, `npy`, `bvh`;
    /// default: from the extension, none meaning an OpenPose folder) — the files
    /// `violin-skeleton generate` writes.
    #[pyo3(signature = (path, format = None))]
    fn save(&self, py: Python<'_>, path: PathBuf, format: Option<&str>) -> PyResult<()> {
        let format = match format {
            Some(name) => SaveFormat::from_name(name)?,
            None => SaveFormat::from_path(&path)?,
        };
        py.detach(|| write_motion(&self.inner, &path, format))?;
        Ok(())
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "<Motion {} frames at {} fps ({:.1} s), {} joints>",
            self.inner.len(),
            self.inner.fps(),
            self.inner.duration_s(),
            Joint::ALL.len()
        )
    }
}
