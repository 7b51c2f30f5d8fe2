//! `Pipeline`: audio (or MIDI) → [`Analysis`] → [`Performance`] → [`Motion`].

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use dsp_mel::{resample, Audio, DEFAULT_ANALYSIS_RATE_HZ};
use fingering::{Fingering, FingeringStyle};
use motion_synth::{synthesize, SynthConfig};
use performance::{Analysis, ArousalCurve, Note};
use pitch_track::{
    segment_notes, split_notes_at, start_notes_at, NoteConfig, PitchConfig, PitchTracker,
};
use skeleton::Motion;

use crate::beats::{self, BeatHints, BeatMethod};
use crate::chunking::Chunking;
use crate::error::Result;
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
    pub(crate) method: Method,
    pub(crate) planner: PlannerKind,
    pub(crate) style: FingeringStyle,
    pub(crate) sul: Vec<SulSpan>,
    pub(crate) transpose_into_range: bool,
    pub(crate) max_duration_s: Option<u32>,
    pub(crate) synth: SynthConfig,
    pub(crate) bowing_file: Option<BowingFile>,
    pub(crate) bowing_network: BowingNetwork,
    pub(crate) emotion_weights: Option<PathBuf>,
    pub(crate) beat_weights: Option<PathBuf>,
    pub(crate) gru_weights: Option<PathBuf>,
    pub(crate) chunking: Chunking,
    pub(crate) beat_method: BeatMethod,
    pub(crate) beat_hints: BeatHints,
    pub(crate) models: Arc<LoadedModels>,
}

impl Pipeline {
    /// This pipeline with other beat hints, sharing its loaded models (e.g. one hint per
    /// recording of a collection).
    pub fn with_beat_hints(&self, hints: BeatHints) -> Pipeline {
        Pipeline {
            beat_hints: hints,
            ..self.clone()
        }
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

    /// The longest input accepted ([`crate::PipelineBuilder::max_duration_s`]), if any.
    pub(crate) fn max_duration(&self) -> Option<f64> {
        self.max_duration_s.map(f64::from)
    }

    /// Refuses beat hints for a MIDI file, whose tempo map and time signatures are used.
    #[cfg(feature = "midi")]
    pub(crate) fn refuse_beat_hints_for_midi(&self) -> Result<()> {
        if self.beat_hints.is_empty() {
            return Ok(());
        }
        Err(crate::error::Error::BeatHint(
            "time-signature and tempo hints apply to audio; a MIDI file's own tempo map and time signatures are used"
                .into(),
        ))
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
        self.beat_hints.check_for(self.beat_method)?;
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
        let end_s = beats::music_end_s(&notes, samples, rate)?;
        let beats = match &activations {
            Some(act) => beats::learned(act, &notes, &bow_changes_s, end_s, &self.beat_hints)?,
            None => beats::classic(samples, &notes, &bow_changes_s, end_s)?,
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
                    return Err(crate::error::Error::TooShort {
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
}
