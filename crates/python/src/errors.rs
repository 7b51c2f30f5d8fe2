//! The crate's error and the Python exceptions it becomes.
//!
//! Every exception derives from `violin_skeleton.ViolinSkeletonError`; the ones about the
//! input also derive from the built-in exception a Python user would catch
//! (`FileNotFoundError`, `IsADirectoryError`, `ValueError`, `TypeError`).

use std::path::{Path, PathBuf};

use pyo3::exceptions::{
    PyException, PyFileNotFoundError, PyIsADirectoryError, PyTypeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};
use violin_skeleton::dsp_mel::DspError;

pyo3::create_exception!(
    violin_skeleton,
    ViolinSkeletonError,
    PyException,
    "Base class of every error raised by violin_skeleton; the message names the file."
);

/// What went wrong in a call from Python.
#[derive(Debug, thiserror::Error)]
pub enum PyApiError {
    /// The input path does not exist.
    #[error("{0}: file not found; check the path")]
    NotFound(PathBuf),
    /// The input path is a directory.
    #[error("{0}: is a directory; pass an audio file (wav, flac, mp3, ogg) or a MIDI file")]
    IsDirectory(PathBuf),
    /// An argument has a wrong value (array shape, NaN, sample rate, format name, …).
    #[error("{0}")]
    InvalidInput(String),
    /// An argument has a wrong type (an integer array, a number where a path is expected).
    #[error("{0}")]
    WrongType(String),
    /// The pipeline failed (decoding, analysis, synthesis, writing a motion).
    #[error(transparent)]
    Pipeline(#[from] violin_skeleton::Error),
    /// An output file could not be written.
    #[error("{path}: {reason}")]
    Output {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
}

/// `Result` with the crate's [`PyApiError`].
pub type Result<T> = std::result::Result<T, PyApiError>;

impl PyApiError {
    /// The pipeline's error, with "the recording" replaced by the file's name.
    pub fn naming(e: violin_skeleton::Error, path: &Path) -> Self {
        use violin_skeleton::Error as E;
        match e {
            E::NoNotes(_) => E::NoNotes(path.display().to_string()).into(),
            E::TooShort {
                duration_s, min_s, ..
            } => E::TooShort {
                source_name: path.display().to_string(),
                duration_s,
                min_s,
            }
            .into(),
            E::Audio(DspError::NotFound { path }) => PyApiError::NotFound(path),
            E::Audio(DspError::IsDirectory { path }) => PyApiError::IsDirectory(path),
            other => other.into(),
        }
    }
}

static NOT_FOUND: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static IS_DIRECTORY: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static INVALID_INPUT: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static WRONG_TYPE: PyOnceLock<Py<PyType>> = PyOnceLock::new();

/// A class `name(ViolinSkeletonError, builtin)` in module `violin_skeleton`.
fn subclass<'py>(
    py: Python<'py>,
    cell: &'static PyOnceLock<Py<PyType>>,
    name: &str,
    builtin: Bound<'py, PyType>,
    doc: &str,
) -> PyResult<Bound<'py, PyType>> {
    let ty = cell.get_or_try_init(py, || -> PyResult<Py<PyType>> {
        let bases = PyTuple::new(
            py,
            [
                py.get_type::<ViolinSkeletonError>().into_any(),
                builtin.into_any(),
            ],
        )?;
        let namespace = PyDict::new(py);
        namespace.set_item("__module__", "violin_skeleton")?;
        namespace.set_item("__doc__", doc)?;
        let made = py
            .get_type::<PyType>()
            .call1((name, bases, namespace))?
            .cast_into::<PyType>()?;
        Ok(made.unbind())
    })?;
    Ok(ty.bind(py).clone())
}

/// `InputNotFoundError(ViolinSkeletonError, FileNotFoundError)`.
pub fn input_not_found(py: Python<'_>) -> PyResult<Bound<'_, PyType>> {
    subclass(
        py,
        &NOT_FOUND,
        "InputNotFoundError",
        py.get_type::<PyFileNotFoundError>(),
        "The input file does not exist.",
    )
}

/// `InputIsDirectoryError(ViolinSkeletonError, IsADirectoryError)`.
pub fn input_is_directory(py: Python<'_>) -> PyResult<Bound<'_, PyType>> {
    subclass(
        py,
        &IS_DIRECTORY,
        "InputIsDirectoryError",
        py.get_type::<PyIsADirectoryError>(),
        "A directory was given where an audio or MIDI file is expected.",
    )
}

/// `InvalidInputError(ViolinSkeletonError, ValueError)`.
pub fn invalid_input(py: Python<'_>) -> PyResult<Bound<'_, PyType>> {
    subclass(
        py,
        &INVALID_INPUT,
        "InvalidInputError",
        py.get_type::<PyValueError>(),
        "An argument has a wrong value: array shape, NaN samples, sample rate, format name.",
    )
}

/// `InputTypeError(ViolinSkeletonError, TypeError)`.
pub fn wrong_type(py: Python<'_>) -> PyResult<Bound<'_, PyType>> {
    subclass(
        py,
        &WRONG_TYPE,
        "InputTypeError",
        py.get_type::<PyTypeError>(),
        "An argument has a wrong type, e.g. an integer array where float samples are expected.",
    )
}

impl From<PyApiError> for PyErr {
    fn from(e: PyApiError) -> PyErr {
        Python::attach(|py| {
            let message = e.to_string();
            let class = match &e {
                PyApiError::NotFound(_) => input_not_found(py),
                PyApiError::IsDirectory(_) => input_is_directory(py),
                PyApiError::InvalidInput(_) => invalid_input(py),
                PyApiError::WrongType(_) => wrong_type(py),
                PyApiError::Pipeline(violin_skeleton::Error::Audio(
                    DspError::EmptyAudio
                    | DspError::InvalidSampleRate(_)
                    | DspError::NonFinite { .. },
                )) => invalid_input(py),
                PyApiError::Pipeline(_) | PyApiError::Output { .. } => {
                    Ok(py.get_type::<ViolinSkeletonError>())
                }
            };
            match class {
                Ok(class) => PyErr::from_type(class, message),
                Err(failed) => failed,
            }
        })
    }
}

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("ViolinSkeletonError", py.get_type::<ViolinSkeletonError>())?;
    m.add("InputNotFoundError", input_not_found(py)?)?;
    m.add("InputIsDirectoryError", input_is_directory(py)?)?;
    m.add("InvalidInputError", invalid_input(py)?)?;
    m.add("InputTypeError", wrong_type(py)?)?;
    Ok(())
}
