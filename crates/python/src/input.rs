//! What the functions accept as audio: a path, or a NumPy array with its sample rate.
//!
//! Arrays: `float32` or `float64` samples (nominally in [-1, 1]), either 1-D (mono) or 2-D
//! with channels on the shorter axis — so librosa's `(channels, samples)` and soundfile's
//! `(samples, channels)` both work — mixed down to mono by averaging the channels, as files
//! are. Everything else is refused with an exception that says what to pass instead.

use std::path::PathBuf;

use ndarray::{ArrayViewD, Axis, Dimension};
use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyFloat;
use violin_skeleton::Audio;

use crate::errors::{PyApiError, Result};

/// More channels than this on the shorter axis means the array is not audio as we take it.
pub const MAX_CHANNELS: usize = 16;

/// The highest sample rate accepted for an array, in Hz (the resampler's limit).
pub const MAX_SAMPLE_RATE_HZ: u32 = 768_000;

/// Audio to work on.
#[derive(Debug)]
pub enum Source {
    /// A file (read by the same code as the command-line tool).
    File(PathBuf),
    /// Samples handed over from Python, already mono.
    Samples(Audio),
}

impl Source {
    /// `path_or_array` and `sr` as the Python functions take them.
    pub fn from_python(obj: &Bound<'_, PyAny>, sr: Option<&Bound<'_, PyAny>>) -> Result<Source> {
        if let Ok(array) = obj.cast::<PyUntypedArray>() {
            let Some(sr) = sr.filter(|s| !s.is_none()) else {
                return Err(PyApiError::InvalidInput(
                    "an audio array needs its sample rate: pass sr=… in Hz (e.g. sr=44100)".into(),
                ));
            };
            let rate = sample_rate(sr)?;
            let samples = mono_samples(array)?;
            let audio = Audio::new(samples, rate).map_err(violin_skeleton::Error::from)?;
            return Ok(Source::Samples(audio));
        }
        if obj.is_instance_of::<PyFloat>() || obj.extract::<i64>().is_ok() {
            return Err(PyApiError::WrongType(format!(
                "expected a path or a NumPy array of samples, got the number {}",
                repr(obj)
            )));
        }
        let Ok(path) = obj.extract::<PathBuf>() else {
            return Err(PyApiError::WrongType(format!(
                "expected a path (str or os.PathLike) or a NumPy array of float samples, got {}; \
                 convert a list with numpy.asarray(x, dtype=numpy.float32)",
                type_name(obj)
            )));
        };
        if sr.is_some_and(|s| !s.is_none()) {
            return Err(PyApiError::InvalidInput(format!(
                "{}: sr is only for arrays; a file is read at its own sample rate",
                path.display()
            )));
        }
        if path.is_dir() {
            return Err(PyApiError::IsDirectory(path));
        }
        if !path.exists() {
            return Err(PyApiError::NotFound(path));
        }
        Ok(Source::File(path))
    }
}

/// `true` for a `.mid` or `.midi` file name (as the command-line tool tells MIDI apart).
pub fn is_midi(path: &std::path::Path) -> bool {
    path.extension().is_some_and(|e| {
        matches!(
            e.to_string_lossy().to_ascii_lowercase().as_str(),
            "mid" | "midi"
        )
    })
}

fn repr(obj: &Bound<'_, PyAny>) -> String {
    obj.repr()
        .map(|r| r.to_string())
        .unwrap_or_else(|_| "?".into())
}

fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "an object".into())
}

/// A positive whole number of Hz.
fn sample_rate(sr: &Bound<'_, PyAny>) -> Result<u32> {
    let hz: f64 = if let Ok(i) = sr.extract::<i64>() {
        i as f64
    } else if let Ok(f) = sr.extract::<f64>() {
        f
    } else {
        return Err(PyApiError::WrongType(format!(
            "sr must be a sample rate in Hz (an int), got {}",
            type_name(sr)
        )));
    };
    if !(hz.is_finite() && hz.fract() == 0.0 && hz >= 1.0 && hz <= f64::from(MAX_SAMPLE_RATE_HZ)) {
        return Err(PyApiError::InvalidInput(format!(
            "sr={}: expected a whole number of Hz between 1 and {MAX_SAMPLE_RATE_HZ} (e.g. 44100)",
            repr(sr)
        )));
    }
    Ok(hz as u32)
}

/// The array's samples as mono `f32`, checked.
fn mono_samples(array: &Bound<'_, PyUntypedArray>) -> Result<Vec<f32>> {
    if let Ok(a) = array.cast::<PyArrayDyn<f32>>() {
        let view = a.try_readonly().map_err(|e| busy(&e.to_string()))?;
        return mono_of(view.as_array());
    }
    if let Ok(a) = array.cast::<PyArrayDyn<f64>>() {
        let view = a.try_readonly().map_err(|e| busy(&e.to_string()))?;
        return mono_of(view.as_array());
    }
    let name = array
        .dtype()
        .str()
        .map(|s| s.to_string())
        .unwrap_or_else(|_| "?".into());
    Err(PyApiError::WrongType(format!(
        "audio array of dtype {name}: expected float32 or float64 samples in [-1, 1]; \
         convert 16-bit PCM with x.astype(numpy.float32) / 32768"
    )))
}

fn busy(reason: &str) -> PyApiError {
    PyApiError::InvalidInput(format!("the audio array cannot be read now ({reason})"))
}

/// Mono samples of a 1-D or 2-D view (channels on the shorter axis).
fn mono_of<T: Copy + Into<f64>>(view: ArrayViewD<'_, T>) -> Result<Vec<f32>> {
    let shape = view.shape().to_vec();
    if view.is_empty() {
        return Err(PyApiError::InvalidInput(format!(
            "the audio array of shape {shape:?} is empty; pass at least one sample"
        )));
    }
    if let Some((index, _)) = view.indexed_iter().find(|(_, v)| !(**v).into().is_finite()) {
        return Err(PyApiError::InvalidInput(format!(
            "the audio array has a NaN or infinite sample at index {:?}; \
             clean it first (e.g. numpy.nan_to_num)",
            index.slice()
        )));
    }
    match view.ndim() {
        1 => Ok(view.iter().map(|&v| v.into() as f32).collect()),
        2 => {
            let channel_axis = if shape[0] <= shape[1] { 0 } else { 1 };
            let channels = shape[channel_axis];
            if channels > MAX_CHANNELS {
                return Err(PyApiError::InvalidInput(format!(
                    "the audio array of shape {shape:?} has {channels} channels on its shorter \
                     axis (at most {MAX_CHANNELS}); pass 1-D mono, (channels, samples) or \
                     (samples, channels)"
                )));
            }
            let scale = 1.0 / channels as f64;
            let mono = view
                .lanes(Axis(channel_axis))
                .into_iter()
                .map(|frame| (frame.iter().map(|&v| v.into()).sum::<f64>() * scale) as f32)
                .collect::<Vec<f32>>();
            Ok(mono)
        }
        n => Err(PyApiError::InvalidInput(format!(
            "the audio array has {n} dimensions (shape {shape:?}); pass 1-D mono samples or \
             2-D (channels, samples) / (samples, channels)"
        ))),
    }
}
