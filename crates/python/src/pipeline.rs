//! `violin_skeleton.Pipeline`: the models loaded once, reused by every call; the work runs
//! without the GIL.

use pyo3::prelude::*;
use violin_skeleton::{
    hint_tempo_range_around, BeatHints, BeatMethod, BowingNetwork, Method, Pipeline, TimeSignature,
};

use crate::analysis::PyAnalysis;
use crate::errors::{PyApiError, Result};
use crate::input::{is_midi, Source};
use crate::motion::PyMotion;

/// The analysis and motion pipeline. Its networks are loaded on first use and kept, so one
/// `Pipeline` analysing many files pays for loading once. Safe to share between threads:
/// calls release the GIL while they work.
#[pyclass(frozen, name = "Pipeline", module = "violin_skeleton")]
pub struct PyPipeline {
    inner: Pipeline,
    method: &'static str,
    beats: &'static str,
    bowing_net: &'static str,
}

fn method_of(name: &str) -> Result<(Method, &'static str)> {
    match name {
        "rules" => Ok((Method::Rules, "rules")),
        "gru" => Ok((Method::Gru, "gru")),
        _ => Err(PyApiError::InvalidInput(format!(
            "method={name:?}: expected \"rules\" (analysis → rule-based motion) or \"gru\" \
             (the learned baseline)"
        ))),
    }
}

fn beats_of(name: &str) -> Result<(BeatMethod, &'static str)> {
    match name {
        "learned" => Ok((BeatMethod::Learned, "learned")),
        "classic" => Ok((BeatMethod::Classic, "classic")),
        _ => Err(PyApiError::InvalidInput(format!(
            "beats={name:?}: expected \"learned\" or \"classic\""
        ))),
    }
}

fn bowing_of(name: &str) -> Result<(BowingNetwork, &'static str)> {
    match name {
        "ensemble" => Ok((BowingNetwork::Ensemble, "ensemble")),
        "strokes" => Ok((BowingNetwork::Strokes, "strokes")),
        "cnn" => Ok((BowingNetwork::Cnn, "cnn")),
        _ => Err(PyApiError::InvalidInput(format!(
            "bowing_net={name:?}: expected \"ensemble\", \"strokes\" or \"cnn\""
        ))),
    }
}

/// `time_signature="3/4"` and `tempo_bpm=120` (±15 %, as the CLI's `--tempo-bpm`) or
/// `(100, 140)`, checked as the CLI checks them.
fn hints_of(
    time_signature: Option<&str>,
    tempo_bpm: Option<&Bound<'_, PyAny>>,
    beats: BeatMethod,
) -> Result<BeatHints> {
    let bad = |what: String| PyApiError::InvalidInput(what);
    let time_signature = time_signature
        .map(|t| {
            t.parse::<TimeSignature>()
                .map_err(|e| bad(format!("time_signature={t:?}: {e}")))
        })
        .transpose()?;
    let tempo_range_bpm = match tempo_bpm {
        None => None,
        Some(v) if v.is_none() => None,
        Some(v) => Some(if let Ok(bpm) = v.extract::<f64>() {
            hint_tempo_range_around(bpm)
        } else if let Ok(range) = v.extract::<(f64, f64)>() {
            range
        } else {
            return Err(bad(
                "tempo_bpm: expected beats per minute (e.g. 120) or a (slowest, fastest) pair"
                    .into(),
            ));
        }),
    };
    let hints = BeatHints {
        time_signature,
        tempo_range_bpm,
    };
    hints.check_for(beats).map_err(|e| bad(e.to_string()))?;
    Ok(hints)
}

impl PyPipeline {
    fn analyze_source(&self, source: &Source) -> Result<violin_skeleton::Analysis> {
        match source {
            Source::File(path) if is_midi(path) => self
                .inner
                .analyze_midi_file(path)
                .map_err(|e| PyApiError::naming(e, path)),
            Source::File(path) => self
                .inner
                .analyze_file(path, |_, _| {})
                .map_err(|e| PyApiError::naming(e, path)),
            Source::Samples(audio) => Ok(self.inner.analyze(audio)?),
        }
    }

    fn generate_source(&self, source: &Source) -> Result<violin_skeleton::Motion> {
        match source {
            Source::File(path) if is_midi(path) => self
                .inner
                .generate_midi(path)
                .map_err(|e| PyApiError::naming(e, path)),
            Source::File(path) => self
                .inner
                .generate_file(path, |_, _| {})
                .map_err(|e| PyApiError::naming(e, path)),
            Source::Samples(audio) => Ok(self.inner.generate(audio)?),
        }
    }
}

#[pymethods]
impl PyPipeline {
    /// A pipeline: `method` makes motion (`"rules"`: analysis → rule-based synthesis;
    /// `"gru"`: the learned baseline), `beats` picks the beat tracker (`"learned"` or
    /// `"classic"`), `bowing_net` the embedded bowing model (`"ensemble"`, `"strokes"`,
    /// `"cnn"`). The defaults are the command-line tool's. What is known of the beat, for
    /// audio: `time_signature` (e.g. `"3/4"`, `"6/8"`) and `tempo_bpm` at the notated beat
    /// (`120`, taken ±15 %, or a `(slowest, fastest)` pair); MIDI files use their own.
    #[new]
    #[pyo3(signature = (method = "rules", beats = "learned", bowing_net = "ensemble", time_signature = None, tempo_bpm = None))]
    fn new(
        method: &str,
        beats: &str,
        bowing_net: &str,
        time_signature: Option<&str>,
        tempo_bpm: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let (m, method) = method_of(method)?;
        let (b, beats) = beats_of(beats)?;
        let (n, bowing_net) = bowing_of(bowing_net)?;
        let hints = hints_of(time_signature, tempo_bpm, b)?;
        let inner = Pipeline::builder()
            .method(m)
            .beat_method(b)
            .bowing_network(n)
            .beat_hints(hints)
            .build();
        Ok(Self {
            inner,
            method,
            beats,
            bowing_net,
        })
    }

    /// The motion method (`"rules"` or `"gru"`).
    #[getter]
    fn method(&self) -> &'static str {
        self.method
    }

    /// Analyses a file (audio or MIDI; any length) or an array of samples at `sr` Hz.
    #[pyo3(signature = (path_or_array, sr = None))]
    fn analyze(
        &self,
        py: Python<'_>,
        path_or_array: &Bound<'_, PyAny>,
        sr: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyAnalysis> {
        let source = Source::from_python(path_or_array, sr)?;
        let analysis = py.detach(|| self.analyze_source(&source))?;
        Ok(PyAnalysis::new(analysis))
    }

    /// Motion (30 fps) for a file (audio or MIDI) or an array of samples at `sr` Hz.
    #[pyo3(signature = (path_or_array, sr = None))]
    fn generate(
        &self,
        py: Python<'_>,
        path_or_array: &Bound<'_, PyAny>,
        sr: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyMotion> {
        let source = Source::from_python(path_or_array, sr)?;
        let motion = py.detach(|| self.generate_source(&source))?;
        Ok(PyMotion::new(motion))
    }

    fn __repr__(&self) -> String {
        format!(
            "Pipeline(method={:?}, beats={:?}, bowing_net={:?})",
            self.method, self.beats, self.bowing_net
        )
    }
}
