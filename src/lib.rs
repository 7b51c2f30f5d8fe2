//! # violin-skeleton
//!
//! Turn a solo violin recording (or a MIDI file) into a plausible violinist skeleton
//! animation at 30 fps: bow strokes that reverse on the real bow changes, a left hand that
//! shifts to where the notes are played, and a body that leans and sways with the music's
//! energy and bars.
//!
//! This crate is the facade: it re-exports the workspace's crates and offers the few entry
//! points most users need — [`Pipeline`] with [`Pipeline::analyze`] (→ [`Analysis`]),
//! [`Pipeline::performance`] (→ [`Performance`]), [`Pipeline::generate`] (→ [`Motion`]) and
//! [`Pipeline::generate_midi`].
//!
//! ```no_run
//! use violin_skeleton::{load_audio, MotionFormat, Pipeline};
//! let audio = load_audio("take1.wav")?;
//! let pipeline = Pipeline::default();
//! let analysis = pipeline.analyze(&audio)?;
//! println!("{} notes, {} bow changes, {:.0} bpm", analysis.notes.len(),
//!          analysis.bow_changes_s.len(), analysis.tempo_bpm);
//! let motion = pipeline.generate_from_analysis(&analysis)?;
//! motion.write("take1_motion.json", MotionFormat::Json)?;
//! # Ok::<(), violin_skeleton::Error>(())
//! ```

mod analysis_performance;
mod beats;
mod builder;
mod chunking;
mod error;
mod fingering_plan;
mod long_audio;
#[cfg(feature = "midi")]
mod midi_analysis;
mod models;
pub mod networks;
mod pipeline;
mod strokes;
mod timings;

pub use beats::{
    hint_tempo_range_around, BeatHints, BeatMethod, HINT_MAX_BEATS_PER_BAR,
    HINT_SINGLE_TEMPO_TOLERANCE, HINT_TEMPO_RANGE_BPM,
};
pub use builder::PipelineBuilder;
pub use chunking::Chunking;
pub use error::{Error, Result};
pub use fingering::{FingeringStyle, ViolinString};
pub use fingering_plan::{PlannerKind, SulSpan};
#[cfg(feature = "midi")]
pub use midi_analysis::MIDI_F0_HOP_S;
pub use networks::BowingNetwork;
pub use performance::{Analysis, ArousalCurve, F0Track, Note};
pub use performance::{BowDirection, BowStroke, Meter, TimeSignature};
pub use pipeline::{
    Method, Pipeline, StageTimings, BOW_CHANGE_ONSET_LEAD_S, BOW_CHANGE_SPLIT_MIN_PART_S,
    MIN_DURATION_S,
};

pub use dsp_mel::{load_audio, load_audio_at, Audio, AudioReader};
pub use motion_synth::{Camera, SynthConfig};
pub use performance::Performance;
pub use skeleton::formats::MotionFormat;
pub use skeleton::{Canvas, Motion, PerformerTrack};

pub use beat_track;
pub use bowing_net;
pub use dsp_mel;
pub use emotion_net;
pub use fingering;
#[cfg(feature = "gru")]
pub use gru_baseline;
pub use motion_synth;
pub use performance;
pub use pitch_track;
pub use skeleton;
#[cfg(feature = "render")]
pub use skeleton_render;
