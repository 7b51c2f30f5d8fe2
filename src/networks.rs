//! The trained models behind the pipeline: the bowing model (stroke network or CNN), the
//! beat/downbeat activation network, the arousal CRNN and the Method 1 GRU. The embedded
//! defaults are loaded once per process and shared.

use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use beat_net::{Activations, BeatActivation};
use bowing_net::stroke::StrokeAnalysis;
use bowing_net::BowingModel;
use dsp_mel::Audio;
use emotion_net::ArousalEstimator;
#[cfg(feature = "gru")]
use gru_baseline::GruBaseline;

use crate::error::{Error, Result};

fn net_err(what: &str, e: impl std::fmt::Display) -> Error {
    Error::Network(format!("{what}: {e}"))
}

/// An error loading the weight file `path`, named once (the crates' load errors usually
/// name the file already).
fn load_err(path: &Path, e: impl std::fmt::Display) -> Error {
    let message = e.to_string();
    let shown = path.display().to_string();
    if message.contains(&shown) {
        Error::Network(message)
    } else {
        Error::Network(format!("{shown}: {message}"))
    }
}

/// A bowing weights file given to the pipeline, and how it is used.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum BowingFile {
    /// Either network, run alone with its own decoder.
    Alone(PathBuf),
    /// Parts of the model a [`BowingNetwork`] chooses from files: a stroke network in place
    /// of the embedded one, the ensemble's CNN in place of the embedded one (`None` keeps
    /// the embedded part).
    Parts {
        /// A `train_strokes` file.
        strokes: Option<PathBuf>,
        /// A `train bowing` file, for the ensemble only.
        cnn: Option<PathBuf>,
    },
}

impl BowingFile {
    /// Parts from files: the given ones replace those of `old` (if it gave parts), the
    /// others are kept; a file run alone is dropped.
    pub(crate) fn with_parts(
        old: Option<Self>,
        strokes: Option<PathBuf>,
        cnn: Option<PathBuf>,
    ) -> Self {
        let (old_strokes, old_cnn) = match old {
            Some(Self::Parts { strokes, cnn }) => (strokes, cnn),
            _ => (None, None),
        };
        Self::Parts {
            strokes: strokes.or(old_strokes),
            cnn: cnn.or(old_cnn),
        }
    }
}

/// Which embedded bowing model the pipeline uses when no weights file is given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BowingNetwork {
    /// The CNN and the stroke network averaged (default): bow changes, and strings from the
    /// stroke network.
    #[default]
    Ensemble,
    /// The stroke network alone: bow changes and strings, trained on the many-violin
    /// corpus.
    Strokes,
    /// The seed design's CNN (SPEC §4): bow changes only; directions come from the rules.
    Cnn,
}

static ENSEMBLE: OnceLock<std::result::Result<Arc<BowingModel>, String>> = OnceLock::new();
static STROKES: OnceLock<std::result::Result<Arc<BowingModel>, String>> = OnceLock::new();
static CNN: OnceLock<std::result::Result<Arc<BowingModel>, String>> = OnceLock::new();
static BEAT: OnceLock<std::result::Result<Arc<BeatActivation>, String>> = OnceLock::new();
static EMOTION: OnceLock<std::result::Result<Arc<ArousalEstimator>, String>> = OnceLock::new();
#[cfg(feature = "gru")]
static GRU: OnceLock<std::result::Result<Arc<GruBaseline>, String>> = OnceLock::new();

/// The embedded bowing model of `network` (loaded once).
pub fn pretrained_bowing(network: BowingNetwork) -> Result<Arc<BowingModel>> {
    let (slot, load): (_, fn() -> bowing_net::Result<BowingModel>) = match network {
        BowingNetwork::Ensemble => (&ENSEMBLE, BowingModel::pretrained),
        BowingNetwork::Strokes => (&STROKES, BowingModel::pretrained_strokes_only),
        BowingNetwork::Cnn => (&CNN, BowingModel::pretrained_cnn),
    };
    slot.get_or_init(|| load().map(Arc::new).map_err(|e| e.to_string()))
        .clone()
        .map_err(|e| net_err("embedded bowing-net weights", e))
}

/// The embedded beat/downbeat activation network (loaded once).
pub fn pretrained_beat() -> Result<Arc<BeatActivation>> {
    BEAT.get_or_init(|| {
        BeatActivation::pretrained()
            .map(Arc::new)
            .map_err(|e| e.to_string())
    })
    .clone()
    .map_err(|e| net_err("embedded beat-net weights", e))
}

/// The embedded arousal estimator (loaded once).
pub fn pretrained_emotion() -> Result<Arc<ArousalEstimator>> {
    EMOTION
        .get_or_init(|| {
            ArousalEstimator::pretrained()
                .map(Arc::new)
                .map_err(|e| e.to_string())
        })
        .clone()
        .map_err(|e| net_err("embedded emotion-net weights", e))
}

/// The embedded Method 1 GRU (loaded once).
#[cfg(feature = "gru")]
pub fn pretrained_gru() -> Result<Arc<GruBaseline>> {
    GRU.get_or_init(|| {
        GruBaseline::pretrained()
            .map(Arc::new)
            .map_err(|e| e.to_string())
    })
    .clone()
    .map_err(|e| net_err("embedded gru-baseline weights", e))
}

/// The bowing model of a weights file ([`BowingFile`]) and an embedded choice.
pub(crate) fn load_bowing_file(
    file: &BowingFile,
    network: BowingNetwork,
) -> Result<Arc<BowingModel>> {
    let (strokes, cnn) = match file {
        BowingFile::Alone(p) => return load_bowing(p),
        BowingFile::Parts { strokes, cnn } => (strokes.as_deref(), cnn.as_deref()),
    };
    let model =
        match (network, strokes, cnn) {
            (BowingNetwork::Ensemble, _, _) => BowingModel::ensemble_from_files(cnn, strokes)
                .map_err(|e| Error::Network(e.to_string()))?,
            (_, _, Some(c)) => {
                return Err(load_err(
                    c,
                    "ensemble-CNN weights were given, but the ensemble was not chosen (choose the \
                 ensemble, or give the file as bowing weights to run the CNN alone)",
                ))
            }
            (BowingNetwork::Strokes, Some(p), None) => {
                BowingModel::Strokes(BowingModel::strokes_file(p).map_err(|e| load_err(p, e))?)
            }
            (BowingNetwork::Cnn, Some(p), None) => return Err(load_err(
                p,
                "stroke-network weights were given, but the CNN alone was chosen, which has no \
                 stroke network to replace (choose the ensemble or the stroke network)",
            )),
            (_, None, None) => return pretrained_bowing(network),
        };
    Ok(Arc::new(model))
}

/// User-trained bowing weights (either network).
pub fn load_bowing(path: &Path) -> Result<Arc<BowingModel>> {
    BowingModel::load(path)
        .map(Arc::new)
        .map_err(|e| load_err(path, e))
}

/// User-trained beat/downbeat weights (`train_beats`).
pub fn load_beat(path: &Path) -> Result<Arc<BeatActivation>> {
    BeatActivation::load(path)
        .map(Arc::new)
        .map_err(|e| load_err(path, e))
}

/// User-trained emotion weights.
pub fn load_emotion(path: &Path) -> Result<Arc<ArousalEstimator>> {
    ArousalEstimator::load(path)
        .map(Arc::new)
        .map_err(|e| load_err(path, e))
}

/// User-trained GRU weights.
#[cfg(feature = "gru")]
pub fn load_gru(path: &Path) -> Result<Arc<GruBaseline>> {
    GruBaseline::load(path)
        .map(Arc::new)
        .map_err(|e| load_err(path, e))
}

/// The 30 fps × 128 mel dB spectrogram both frame networks read, of `audio` (analysis rate).
pub fn mel30(audio: &Audio) -> Result<ndarray::Array2<f32>> {
    bowing_net::features::bowing_mel(audio).map_err(|e| net_err("mel spectrogram", e))
}

/// Bow changes, played stretches and strings from the 30 fps mel ([`mel30`]).
pub fn bowing_of_mel(model: &BowingModel, mel: ndarray::ArrayView2<f32>) -> Result<StrokeAnalysis> {
    model
        .analyze_mel(mel)
        .map_err(|e| net_err("bow-change detection", e))
}

/// Beat and downbeat activations (30 fps) from the 30 fps mel ([`mel30`]).
pub fn beat_activations(
    net: &BeatActivation,
    mel: ndarray::ArrayView2<f32>,
) -> Result<Activations> {
    net.activations(mel)
        .map_err(|e| net_err("beat activation", e))
}

/// Arousal at 2 Hz for `audio`, one value per half second of `duration_s`.
pub fn arousal(estimator: &ArousalEstimator, audio: &Audio, duration_s: f64) -> Result<Vec<f32>> {
    let mut values = estimator
        .predict_audio(audio)
        .map_err(|e| net_err("arousal estimation", e))?;
    let n = ((duration_s * 2.0).ceil() as usize).max(1);
    let last = values.last().copied().unwrap_or(0.0);
    values.resize(n, last);
    for v in &mut values {
        *v = if v.is_finite() {
            v.clamp(-1.0, 1.0)
        } else {
            0.0
        };
    }
    Ok(values)
}

/// Method 1: the GRU's motion for `audio`.
#[cfg(feature = "gru")]
pub fn gru_motion(gru: &GruBaseline, audio: &Audio) -> Result<skeleton::Motion> {
    gru.generate(audio).map_err(|e| net_err("gru-baseline", e))
}
