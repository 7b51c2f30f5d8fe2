//! The networks one [`crate::Pipeline`] uses, each loaded once per pipeline on first use
//! (from the weight file given to the builder, or the embedded default, itself decoded once
//! per process) and shared by the pipeline's clones.

use std::path::Path;
use std::sync::{Arc, OnceLock};

use beat_net::BeatActivation;
use bowing_net::BowingModel;
use emotion_net::ArousalEstimator;

use crate::error::{Error, Result};
use crate::networks;

/// A network, once loaded (or the message of the error that loading it gave).
type Slot<T> = OnceLock<std::result::Result<Arc<T>, String>>;

fn get<T>(slot: &Slot<T>, load: impl FnOnce() -> Result<Arc<T>>) -> Result<Arc<T>> {
    slot.get_or_init(|| load().map_err(|e| e.to_string()))
        .clone()
        .map_err(Error::Network)
}

/// The loaded networks of a pipeline.
#[derive(Default)]
pub(crate) struct LoadedModels {
    bowing: Slot<BowingModel>,
    beat: Slot<BeatActivation>,
    emotion: Slot<ArousalEstimator>,
    #[cfg(feature = "gru")]
    gru: Slot<gru_baseline::GruBaseline>,
}

impl std::fmt::Debug for LoadedModels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoadedModels")
            .field("bowing", &self.bowing.get().is_some())
            .field("beat", &self.beat.get().is_some())
            .field("emotion", &self.emotion.get().is_some())
            .finish_non_exhaustive()
    }
}

impl LoadedModels {
    /// The bowing model: from `file` ([`networks::BowingFile`]), or the embedded default of
    /// `network`.
    pub(crate) fn bowing(
        &self,
        file: Option<&networks::BowingFile>,
        network: networks::BowingNetwork,
    ) -> Result<Arc<BowingModel>> {
        get(&self.bowing, || match file {
            Some(f) => networks::load_bowing_file(f, network),
            None => networks::pretrained_bowing(network),
        })
    }

    /// The beat/downbeat activation network: from `path`, or the embedded default.
    pub(crate) fn beat(&self, path: Option<&Path>) -> Result<Arc<BeatActivation>> {
        get(&self.beat, || match path {
            Some(p) => networks::load_beat(p),
            None => networks::pretrained_beat(),
        })
    }

    /// The arousal estimator: from `path`, or the embedded default.
    pub(crate) fn emotion(&self, path: Option<&Path>) -> Result<Arc<ArousalEstimator>> {
        get(&self.emotion, || match path {
            Some(p) => networks::load_emotion(p),
            None => networks::pretrained_emotion(),
        })
    }

    /// The Method 1 GRU: from `path`, or the embedded default.
    #[cfg(feature = "gru")]
    pub(crate) fn gru(&self, path: Option<&Path>) -> Result<Arc<gru_baseline::GruBaseline>> {
        get(&self.gru, || match path {
            Some(p) => networks::load_gru(p),
            None => networks::pretrained_gru(),
        })
    }
}
