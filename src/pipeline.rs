//! `Pipeline`: audio (or MIDI) → [`Analysis`] → [`Performance`] → [`Motion`].

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use dsp_mel::{resample, Audio, DEFAULT_ANALYSIS_RATE_HZ};
use fingering::{Fingering, FingeringStyle, ViolinString};
use motion_synth::{synthesize, Camera, SynthConfig};
use performance::{Analysis, ArousalCurve, Note, Performance};
use pitch_track::{
    segment_notes, split_notes_at, start_notes_at, NoteConfig, PitchConfig, PitchTracker,
};
use skeleton::Motion;

use crate::beats::{self, BeatMethod};
use crate::chunking::Chunking;
use crate::error::{Error, Result};
use crate::fingering_plan::{plan_notes, PlannerKind, SulSpan};
use crate::models::LoadedModels;
use crate::networks::{self, BowingFile, BowingNetwork};
pub use crate::timings::StageTimings;

/// How motion is made from the music.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Method 2 (default): analysis → performance → rule-based synthesis.
    #[default]
    Rules,
    /// Method 1: the GRU baseline maps mel frames straight to joints (feature `gru`).
    #[cfg(feature = "gru")]
    Gru,
}

/// The shortest recording the pipeline makes motion for, in seconds (one bow stroke);
/// shorter audio can still be analysed.
pub const MIN_DURATION_S: f64 = 1.0;

/// A bow change splits a note only when both parts last at least this long (seconds): near a
/// note's ends it is most likely that note's own onset (or the next one's), seen by both
/// detectors a frame or two apart. Chosen with [`BOW_CHANGE_ONSET_LEAD_S`] on the training and
/// validation splits of corpus-mix (151 items; 0.06–0.2 s × 0.03–0.08 s), with the shipped
/// bowing-net weights (trained on another corpus): note-onset F1 0.883 at the former
/// 0.2 s / 0.03 s, 0.916 at 0.06 s / 0.06 s; on 480 held-out items (seed 4242) 0.884 → 0.917.
pub const BOW_CHANGE_SPLIT_MIN_PART_S: f64 = 0.06;

/// A note whose onset comes less than this long (seconds) after a bow change starts at the
/// bow change: the pitch path confirms a new pitch only after a few frames of it, and a
/// SoundFont's new bow is heard a median 34 ms after it starts. Chosen with
/// [`BOW_CHANGE_SPLIT_MIN_PART_S`]; longer leads trade the built-in renderer's onsets for the
/// SoundFont's (0.08 s: built-in −0.011, SoundFont +0.004 on the tuning set).
pub const BOW_CHANGE_ONSET_LEAD_S: f64 = 0.06;

/// The whole product behind one value. Build it with [`Pipeline::builder`] or use
/// [`Pipeline::default`] (Method 2, optimal fingering, embedded models, default camera).
///
/// ```no_run
/// use violin_skeleton::{load_audio, MotionFormat, Pipeline};
/// let audio = load_audio("take1.wav")?;
/// let motion = Pipeline::default().generate(&audio)?;
/// motion.write("take1.json", MotionFormat::Json)?;
/// # Ok::<(), violin_skeleton::Error>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct Pipeline {
    method: Method,
    planner: PlannerKind,
    style: FingeringStyle,
    sul: Vec<SulSpan>,
    transpose_into_range: bool,
    max_duration_s: Option<u32>,
    synth: SynthConfig,
    bowing_file: Option<BowingFile>,
    bowing_network: BowingNetwork,
    emotion_weights: Option<PathBuf>,
    beat_weights: Option<PathBuf>,
    gru_weights: Option<PathBuf>,
    chunking: Chunking,
    beat_method: BeatMethod,
    models: Arc<LoadedModels>,
}

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

    /// The synthesis settings.
    pub fn synth_config(&self) -> &SynthConfig {
        &self.synth
    }

    /// The motion method.
    pub fn method(&self) -> Method {
        self.method
    }

    /// How long files are cut.
    pub fn chunking(&self) -> Chunking {
        self.chunking
    }

    /// One place per note (`None` where no violin place plays it), double stops on
    /// neighbouring strings.
    pub fn plan(&self, notes: &[Note]) -> Vec<Option<Fingering>> {
        plan_notes(self.planner, &self.style, &self.sul, notes)
    }

    /// Whether the bowing model decodes stroke directions from the audio (its weights
    /// carry a direction decoder).
    pub(crate) fn hears_directions(&self) -> Result<bool> {
        Ok(self
            .models
            .bowing(self.bowing_file.as_ref(), self.bowing_network)?
            .direction_decoder()
            .is_some())
    }

    /// The longest input accepted ([`PipelineBuilder::max_duration_s`]), if any.
    pub(crate) fn max_duration(&self) -> Option<f64> {
        self.max_duration_s.map(f64::from)
    }

    /// The MIDI reading options.
    #[cfg(feature = "midi")]
    pub(crate) fn midi_options(&self) -> performance::midi::MidiOptions {
        let defaults = performance::midi::MidiOptions::default();
        performance::midi::MidiOptions {
            transpose_into_range: self.transpose_into_range,
            max_duration_s: self.max_duration_s.unwrap_or(defaults.max_duration_s),
        }
    }

    /// Analyses a recording: f0 and notes (pYIN-class tracker), fingering, beats, downbeats
    /// and tempo, bow changes and arousal.
    pub fn analyze(&self, audio: &Audio) -> Result<Analysis> {
        self.analyze_timed(audio).map(|(a, _)| a)
    }

    /// [`Pipeline::analyze`], also telling how long each stage took.
    pub fn analyze_timed(&self, audio: &Audio) -> Result<(Analysis, StageTimings)> {
        let mut timings = StageTimings::default();
        let clock = Instant::now();
        let analysed = resample(audio, DEFAULT_ANALYSIS_RATE_HZ)?;
        timings.resample_s = clock.elapsed().as_secs_f64();
        let samples = analysed.samples();
        let rate = analysed.sample_rate_hz();
        // The score side (pitch, notes) and the networks (bow changes, arousal) do not
        // depend on each other: run them on both cores at once. Beats need both.
        let score_side = || -> Result<_> {
            let clock = Instant::now();
            let track = PitchTracker::new(PitchConfig::default())?.track(samples)?;
            let notes = segment_notes(&track, samples, rate, &NoteConfig::default())?;
            Ok((track, notes, clock.elapsed().as_secs_f64()))
        };
        let network_side = || -> Result<_> {
            let clock = Instant::now();
            // One 30 fps mel for the two frame networks.
            let mel = networks::mel30(&analysed)?;
            let bowing = self
                .models
                .bowing(self.bowing_file.as_ref(), self.bowing_network)?;
            let bowed = networks::bowing_of_mel(&bowing, mel.view())?;
            let activations = match self.beat_method {
                BeatMethod::Learned => Some(networks::beat_activations(
                    &*self.models.beat(self.beat_weights.as_deref())?,
                    mel.view(),
                )?),
                BeatMethod::Classic => None,
            };
            let bowing_s = clock.elapsed().as_secs_f64();
            let clock = Instant::now();
            let emotion = self.models.emotion(self.emotion_weights.as_deref())?;
            let arousal = networks::arousal(&emotion, &analysed, audio.duration_s())?;
            Ok((
                bowed,
                activations,
                arousal,
                bowing_s,
                clock.elapsed().as_secs_f64(),
            ))
        };
        let (score, nets) = rayon::join(score_side, network_side);
        let (track, notes, pitch_s) = score?;
        let (bowed, activations, arousal, bowing_s, arousal_s) = nets?;
        let bow_changes_s = bowed.bow_changes_s.clone();
        let clock = Instant::now();
        let beats = match &activations {
            Some(act) => beats::learned(act, &notes, &bow_changes_s)?,
            None => beats::classic(samples, &notes, &bow_changes_s)?,
        };
        let beats_s = clock.elapsed().as_secs_f64();
        timings.pitch_s = pitch_s;
        timings.beats_s = beats_s;
        timings.bowing_s = bowing_s;
        timings.arousal_s = arousal_s;
        // Every bow change starts a note, even on the same pitch, where the attack may be
        // too soft for the pitch path or the onset novelty.
        let notes = split_notes_at(&notes, &bow_changes_s, BOW_CHANGE_SPLIT_MIN_PART_S);
        let notes = start_notes_at(&notes, &bow_changes_s, BOW_CHANGE_ONSET_LEAD_S);
        let places = self.plan(&notes);
        let analyzed_notes: Vec<Note> = notes
            .iter()
            .zip(places)
            .map(|(n, f)| Note { fingering: f, ..*n })
            .collect();
        let bow_directions = bowed.directions(
            &bow_changes_s,
            &analyzed_notes,
            &beats.beats_s,
            &beats.downbeats_s,
        );
        let bow_strokes = crate::strokes::strokes_with_strings(
            &bowed,
            &bow_changes_s,
            &bow_directions,
            &analyzed_notes,
        );
        let tempo_bpm_per_beat = performance::tempo_per_beat(&beats.beats_s);
        let analysis = Analysis {
            schema_version: performance::ANALYSIS_SCHEMA_VERSION,
            source: "audio".into(),
            duration_s: audio.duration_s(),
            sample_rate: audio.sample_rate_hz(),
            f0: track.to_f0_track(),
            notes: analyzed_notes,
            bow_changes_s,
            bow_directions,
            bow_strokes,
            beats_s: beats.beats_s,
            downbeats_s: beats.downbeats_s,
            tempo_bpm_per_beat,
            tempo_bpm: beats.tempo_bpm,
            meter: beats.meter,
            beat_confidence: beats.confidence,
            arousal: ArousalCurve::deam(arousal),
        };
        Ok((analysis, timings))
    }

    /// Motion for a recording, 30 fps.
    pub fn generate(&self, audio: &Audio) -> Result<Motion> {
        match self.method {
            Method::Rules => {
                let analysis = self.analyze(audio)?;
                self.generate_from_analysis(&analysis)
            }
            #[cfg(feature = "gru")]
            Method::Gru => {
                if audio.duration_s() < MIN_DURATION_S {
                    return Err(Error::TooShort {
                        source_name: "the recording".into(),
                        duration_s: audio.duration_s(),
                        min_s: MIN_DURATION_S,
                    });
                }
                let gru = self.models.gru(self.gru_weights.as_deref())?;
                networks::gru_motion(&gru, audio)
            }
        }
    }

    /// Motion for an analysis (Method 2).
    pub fn generate_from_analysis(&self, analysis: &Analysis) -> Result<Motion> {
        let perf = self.performance(analysis)?;
        Ok(synthesize(&perf, &self.synth)?)
    }

    /// Motion for a MIDI file: notes and timing from the file, bowing from slur and
    /// articulation heuristics, arousal from velocity (see `performance::midi`).
    #[cfg(feature = "midi")]
    pub fn generate_midi(&self, path: impl AsRef<std::path::Path>) -> Result<Motion> {
        let perf = self.performance_from_midi(path)?;
        Ok(synthesize(&perf, &self.synth)?)
    }

    /// The [`Performance`] of a MIDI file (its melodic line; see `performance::midi`).
    #[cfg(feature = "midi")]
    pub fn performance_from_midi(&self, path: impl AsRef<std::path::Path>) -> Result<Performance> {
        let mut timeline =
            performance::midi::timeline_from_midi_file_with(path, &self.midi_options())?;
        let notes: Vec<Note> = timeline.notes.iter().map(|n| n.note).collect();
        for (n, f) in timeline.notes.iter_mut().zip(self.plan(&notes)) {
            n.note.fingering = f;
        }
        Ok(timeline.to_performance()?)
    }
}
