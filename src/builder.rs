//! [`PipelineBuilder`]: every choice a [`Pipeline`] makes, set one at a time.

use std::path::PathBuf;
use std::sync::Arc;

use fingering::{FingeringStyle, ViolinString};
use motion_synth::{Camera, SynthConfig};

use crate::beats::{BeatHints, BeatMethod};
use crate::chunking::Chunking;
use crate::fingering_plan::{PlannerKind, SulSpan};
use crate::networks::{BowingFile, BowingNetwork};
use crate::pipeline::{Method, Pipeline};

/// Builder of a [`Pipeline`].
#[derive(Debug, Clone, Default)]
pub struct PipelineBuilder {
    inner: Pipeline,
}

impl PipelineBuilder {
    /// Method 1 (GRU) or Method 2 (rules, default).
    pub fn method(mut self, method: Method) -> Self {
        self.inner.method = method;
        self
    }

    /// The fingering planner.
    pub fn planner(mut self, planner: PlannerKind) -> Self {
        self.inner.planner = planner;
        self
    }

    /// Style knobs of the optimal and learned planners: open strings, low or high
    /// positions ([`FingeringStyle`]; its `sul` passages count notes — use
    /// [`PipelineBuilder::sul`] for passages in seconds). The greedy rule has no knobs.
    pub fn fingering_style(mut self, style: FingeringStyle) -> Self {
        self.inner.style = style;
        self
    }

    /// Keeps the notes starting in `[from_s, to_s)` on `string` wherever it can play them
    /// (*sul G* etc.; optimal and learned planners).
    pub fn sul(mut self, string: ViolinString, from_s: f64, to_s: f64) -> Self {
        self.inner.sul.push(SulSpan {
            string,
            from_s,
            to_s,
        });
        self
    }

    /// MIDI input: move notes outside G3..A7 by octaves into the range instead of refusing
    /// the file.
    pub fn transpose_into_range(mut self, yes: bool) -> Self {
        self.inner.transpose_into_range = yes;
        self
    }

    /// Refuse inputs longer than this many seconds: audio whose container announces a longer
    /// length (or that runs past it while being read) and MIDI files whose notes sound past
    /// it. Default: audio of any length (it is analysed in pieces), MIDI up to
    /// [`performance::midi::MAX_DURATION_S`].
    pub fn max_duration_s(mut self, seconds: u32) -> Self {
        self.inner.max_duration_s = Some(seconds);
        self
    }

    /// The camera that projects the 3-D rig to pixels.
    pub fn camera(mut self, camera: Camera) -> Self {
        self.inner.synth.camera = camera;
        self
    }

    /// All synthesis settings at once (rig, camera, frame rate, …).
    pub fn synth_config(mut self, cfg: SynthConfig) -> Self {
        self.inner.synth = cfg;
        self
    }

    /// Bowing weights trained with `violin-skeleton train bowing` or the `train_strokes`
    /// example (the stroke network or the CNN, told apart by the file). The file's network
    /// runs alone, with its own decoder: it is not averaged with the other network, and
    /// [`PipelineBuilder::bowing_network`] is then not used (to run a retrained stroke
    /// network inside the ensemble, see [`PipelineBuilder::stroke_weights`]). Replaces an
    /// earlier `stroke_weights` or `ensemble_cnn_weights`. Default: the embedded model that
    /// [`PipelineBuilder::bowing_network`] chooses (the ensemble).
    pub fn bowing_weights(mut self, path: impl Into<PathBuf>) -> Self {
        self.inner.bowing_file = Some(BowingFile::Alone(path.into()));
        self
    }

    /// Stroke-network weights from the `train_strokes` example in place of the embedded
    /// stroke network, inside the model [`PipelineBuilder::bowing_network`] chooses: with
    /// [`BowingNetwork::Ensemble`] (the default) averaged with the embedded CNN and picked by
    /// the file's ensemble decoder, exactly as the shipped model is; with
    /// [`BowingNetwork::Strokes`] alone. With [`BowingNetwork::Cnn`], or a file without an
    /// ensemble decoder for the ensemble, analysis fails with an error naming the file.
    /// Replaces an earlier `bowing_weights`.
    pub fn stroke_weights(mut self, path: impl Into<PathBuf>) -> Self {
        let old = self.inner.bowing_file.take();
        self.inner.bowing_file = Some(BowingFile::with_parts(old, Some(path.into()), None));
        self
    }

    /// Bow-change CNN weights from `violin-skeleton train bowing` in place of the embedded
    /// ensemble's CNN, averaged with the stroke network (the embedded one, or a
    /// [`PipelineBuilder::stroke_weights`] file) by the stroke network's ensemble decoder.
    /// Only for [`BowingNetwork::Ensemble`]: with another network, or a stroke-network file,
    /// analysis fails with an error naming the file. Replaces an earlier `bowing_weights`.
    pub fn ensemble_cnn_weights(mut self, path: impl Into<PathBuf>) -> Self {
        let old = self.inner.bowing_file.take();
        self.inner.bowing_file = Some(BowingFile::with_parts(old, None, Some(path.into())));
        self
    }

    /// The embedded bowing model used when no weights file is given, or the model a
    /// [`PipelineBuilder::stroke_weights`] file goes into.
    pub fn bowing_network(mut self, network: BowingNetwork) -> Self {
        self.inner.bowing_network = network;
        self
    }

    /// Arousal CRNN weights trained with `violin-skeleton train emotion`.
    pub fn emotion_weights(mut self, path: impl Into<PathBuf>) -> Self {
        self.inner.emotion_weights = Some(path.into());
        self
    }

    /// Beat/downbeat activation weights trained with the `train_beats` example (used with
    /// [`BeatMethod::Learned`]).
    pub fn beat_weights(mut self, path: impl Into<PathBuf>) -> Self {
        self.inner.beat_weights = Some(path.into());
        self
    }

    /// Method 1 GRU weights trained with `violin-skeleton train gru`.
    pub fn gru_weights(mut self, path: impl Into<PathBuf>) -> Self {
        self.inner.gru_weights = Some(path.into());
        self
    }

    /// The beat tracker of the audio analysis (default: learned).
    pub fn beat_method(mut self, method: BeatMethod) -> Self {
        self.inner.beat_method = method;
        self
    }

    /// What the user knows about the beat: the time signature and/or the tempo range
    /// (audio with the learned beat tracker only; checked when a recording is analysed).
    pub fn beat_hints(mut self, hints: BeatHints) -> Self {
        self.inner.beat_hints = hints;
        self
    }

    /// How files longer than three minutes are cut for [`Pipeline::analyze_file`].
    pub fn chunking(mut self, chunking: Chunking) -> Self {
        self.inner.chunking = chunking;
        self
    }

    /// The pipeline. Weight files given to the builder are read when first needed, and a
    /// file that does not fit is reported then.
    pub fn build(mut self) -> Pipeline {
        self.inner.models = Arc::default();
        self.inner
    }
}

impl Pipeline {
    /// A builder starting from the defaults.
    pub fn builder() -> PipelineBuilder {
        PipelineBuilder::default()
    }
}
