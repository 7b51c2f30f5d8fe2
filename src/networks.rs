//! The trained models behind the pipeline: the bow-change CNN, the arousal CRNN and the
//! Method 1 GRU. The embedded defaults are loaded once per process and shared.

use std::path::Path;
use std::sync::{Arc, OnceLock};

use beat_net::{Activations, BeatActivation};
use bowing_net::BowChangeDetector;
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

static BOWING: OnceLock<std::result::Result<Arc<BowChangeDetector>, String>> = OnceLock::new();
static BEAT: OnceLock<std::result::Result<Arc<BeatActivation>, String>> = OnceLock::new();
static EMOTION: OnceLock<std::result::Result<Arc<ArousalEstimator>, String>> = OnceLock::new();
#[cfg(feature = "gru")]
static GRU: OnceLock<std::result::Result<Arc<GruBaseline>, String>> = OnceLock::new();

/// The embedded bow-change detector (loaded once).
pub fn pretrained_bowing() -> Result<Arc<BowChangeDetector>> {
    BOWING
        .get_or_init(|| {
            BowChangeDetector::pretrained()
                .map(Arc::new)
                .map_err(|e| e.to_string())
        })
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

/// User-trained bowing weights.
pub fn load_bowing(path: &Path) -> Result<Arc<BowChangeDetector>> {
    BowChangeDetector::load(path)
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

/// Bow changes (seconds) in `audio` (analysis rate).
pub fn bow_changes(detector: &BowChangeDetector, audio: &Audio) -> Result<Vec<f64>> {
    detector
        .detect_audio(audio)
        .map_err(|e| net_err("bow-change detection", e))
}

/// The 30 fps × 128 mel dB spectrogram both frame networks read, of `audio` (analysis rate).
pub fn mel30(audio: &Audio) -> Result<ndarray::Array2<f32>> {
    bowing_net::features::bowing_mel(audio).map_err(|e| net_err("mel spectrogram", e))
}

/// Bow changes (seconds) from the 30 fps mel ([`mel30`]), as
/// [`BowChangeDetector::detect_audio`] finds them.
pub fn bow_changes_of_mel(
    detector: &BowChangeDetector,
    mel: ndarray::ArrayView2<f32>,
) -> Result<Vec<f64>> {
    let probs = detector
        .frame_probabilities(mel)
        .map_err(|e| net_err("bow-change detection", e))?;
    Ok(detector
        .decoder()
        .pick_fractional(&probs)
        .into_iter()
        .map(|f| f / bowing_net::features::FPS)
        .collect())
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
