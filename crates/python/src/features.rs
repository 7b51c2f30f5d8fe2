//! `violin_skeleton.features`: the networks' mel inputs, as `violin-skeleton features` writes
//! them (dB, 22 050 Hz analysis rate).

use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use violin_skeleton::dsp_mel::{
    load_audio, resample, DbConfig, MelConfig, MelSpectrogram, DEFAULT_ANALYSIS_RATE_HZ,
};

use crate::errors::{PyApiError, Result};
use crate::input::{is_midi, Source};

/// The mel features of `source` (`kind` is `mel30` or `mel2`), frames × bands.
fn mel_of(source: Source, kind: MelConfig) -> Result<ndarray::Array2<f32>> {
    let audio = match source {
        Source::File(path) if is_midi(&path) => {
            return Err(PyApiError::InvalidInput(format!(
                "{}: features are computed from audio, not MIDI",
                path.display()
            )))
        }
        Source::File(path) => load_audio(&path).map_err(|e| PyApiError::naming(e.into(), &path))?,
        Source::Samples(audio) => audio,
    };
    let audio = resample(&audio, DEFAULT_ANALYSIS_RATE_HZ).map_err(violin_skeleton::Error::from)?;
    let mel = MelSpectrogram::new(kind.at_sample_rate(audio.sample_rate_hz()))
        .map_err(violin_skeleton::Error::from)?;
    Ok(mel
        .compute_db(audio.samples(), &DbConfig::default())
        .map_err(violin_skeleton::Error::from)?)
}

/// The networks' input features of a file or an array of samples at `sr` Hz: `kind="mel30"`
/// (30 frames/s × 128 mel bands) or `"mel2"` (the emotion network's 64 bands), in dB, as a
/// float32 array of shape (frames, bands) — what `violin-skeleton features` writes.
#[pyfunction]
#[pyo3(signature = (path_or_array, kind = "mel30", sr = None))]
pub fn features<'py>(
    py: Python<'py>,
    path_or_array: &Bound<'py, PyAny>,
    kind: &str,
    sr: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let config = match kind {
        "mel30" => MelConfig::bowing(),
        "mel2" => MelConfig::emotion(),
        _ => {
            return Err(PyApiError::InvalidInput(format!(
                "kind={kind:?}: expected \"mel30\" or \"mel2\""
            ))
            .into())
        }
    };
    let source = Source::from_python(path_or_array, sr)?;
    let mel = py.detach(|| mel_of(source, config))?;
    Ok(mel.into_pyarray(py))
}
