//! `violin_skeleton.Analysis`: what the analysis found, as NumPy arrays and plain Python
//! values, and the same `analysis.json` the command-line tool writes.

use std::path::PathBuf;

use numpy::{PyArray1, ToPyArray};
use pyo3::prelude::*;

use crate::errors::{PyApiError, Result};
use crate::output::write_file;

/// The analysis of a recording (or MIDI file): f0, notes with fingering, bow changes, beats,
/// downbeats, tempo and arousal. Times are in seconds from the start of the input.
#[pyclass(frozen, name = "Analysis", module = "violin_skeleton")]
pub struct PyAnalysis {
    inner: violin_skeleton::Analysis,
}

impl PyAnalysis {
    /// Wraps an analysis.
    pub fn new(inner: violin_skeleton::Analysis) -> Self {
        Self { inner }
    }

    /// The analysis as `analysis.json` text (the command-line tool's bytes).
    fn json(&self) -> Result<String> {
        serde_json::to_string(&self.inner)
            .map_err(|e| PyApiError::InvalidInput(format!("the analysis cannot be encoded: {e}")))
    }
}

#[pymethods]
impl PyAnalysis {
    /// Length of the input in seconds.
    #[getter]
    fn duration_s(&self) -> f64 {
        self.inner.duration_s
    }

    /// Sample rate of the input in Hz (0 for MIDI); the analysis itself runs at 22 050 Hz.
    #[getter]
    fn sample_rate(&self) -> u32 {
        self.inner.sample_rate
    }

    /// `"audio"` or `"midi"`.
    #[getter]
    fn source(&self) -> &str {
        &self.inner.source
    }

    /// Seconds between f0 frames.
    #[getter]
    fn f0_hop_s(&self) -> f64 {
        self.inner.f0.hop_s
    }

    /// f0 per frame in Hz (float32), 0 where unvoiced (as in analysis.json).
    #[getter]
    fn f0_hz<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        self.inner.f0.hz.to_pyarray(py)
    }

    /// Probability that each f0 frame is voiced (float32).
    #[getter]
    fn voiced_prob<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        self.inner.f0.voiced_prob.to_pyarray(py)
    }

    /// Beat times in seconds (float64).
    #[getter]
    fn beats_s<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.beats_s.to_pyarray(py)
    }

    /// Downbeat (bar start) times in seconds (float64).
    #[getter]
    fn downbeats_s<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.downbeats_s.to_pyarray(py)
    }

    /// Bow change times in seconds (float64).
    #[getter]
    fn bow_changes_s<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.bow_changes_s.to_pyarray(py)
    }

    /// Arousal in [-1, 1] at `arousal_rate_hz` values per second (float32).
    #[getter]
    fn arousal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        self.inner.arousal.values.to_pyarray(py)
    }

    /// Values per second of `arousal` (2).
    #[getter]
    fn arousal_rate_hz(&self) -> f64 {
        self.inner.arousal.rate_hz
    }

    /// The overall tempo in beats per minute.
    #[getter]
    fn tempo_bpm(&self) -> f64 {
        self.inner.tempo_bpm
    }

    /// The notes, one dict each with analysis.json's keys: `onset_s`, `offset_s`, `midi`,
    /// and `string`, `position`, `finger` where a violin place plays the note.
    #[getter]
    fn notes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.to_dict(py)?.get_item("notes")
    }

    /// Everything as plain Python values, with the keys and values of analysis.json.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = self.json()?;
        py.import("json")?.call_method1("loads", (text,))
    }

    /// The analysis.json text.
    fn to_json(&self) -> PyResult<String> {
        Ok(self.json()?)
    }

    /// Writes analysis.json to `path` atomically: the bytes `violin-skeleton analyze` writes.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let text = self.json()?;
        py.detach(|| write_file(&path, text.as_bytes()))?;
        Ok(())
    }

    fn __repr__(&self) -> String {
        format!(
            "<Analysis {:.1} s: {} notes, {} bow changes, {} beats, {:.1} bpm>",
            self.inner.duration_s,
            self.inner.notes.len(),
            self.inner.bow_changes_s.len(),
            self.inner.beats_s.len(),
            self.inner.tempo_bpm
        )
    }
}
