//! [`Analysis`]: what a recording tells — f0, notes with fingering, bow changes, beats,
//! downbeats, tempo and arousal — in the `analysis.json` schema of ARCHITECTURE.md.

use serde::{Deserialize, Serialize};

use crate::arousal::ArousalCurve;
use crate::bowing::BowDirection;
use crate::meter::Meter;
use crate::note::Note;
use crate::stroke::BowStroke;

/// The `analysis.json` schema version this crate writes: 2 added `schema_version`,
/// `source`, `meter`, `bow_directions` and the notes' `velocity`; 3 added `bow_strokes`
/// (files without `schema_version` are version 1 and still read).
pub const ANALYSIS_SCHEMA_VERSION: u32 = 3;

fn version_1() -> u32 {
    1
}

fn audio() -> String {
    "audio".into()
}

/// Frame-wise fundamental frequency (`pitch_track::PitchTrack` converts to and from it and
/// resamples it to the skeleton's frame rate).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct F0Track {
    /// Seconds between frames.
    pub hop_s: f64,
    /// f0 in Hz per frame; 0 where unvoiced (JSON has no NaN).
    pub hz: Vec<f32>,
    /// Probability that each frame is voiced.
    pub voiced_prob: Vec<f32>,
}

/// Everything the analysis found in a recording (or read from a MIDI file).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Analysis {
    /// Schema version ([`ANALYSIS_SCHEMA_VERSION`]; 1 when the file has none).
    #[serde(default = "version_1")]
    pub schema_version: u32,
    /// Where the analysis comes from: `"audio"` or `"midi"`.
    #[serde(default = "audio")]
    pub source: String,
    /// Length of the recording in seconds.
    pub duration_s: f64,
    /// Sample rate of the input in Hz (the analysis runs at 22 050 Hz); 0 for MIDI input.
    pub sample_rate: u32,
    /// Fundamental frequency.
    pub f0: F0Track,
    /// Notes, in time order.
    pub notes: Vec<Note>,
    /// Bow changes in seconds.
    pub bow_changes_s: Vec<f64>,
    /// The direction of the stroke each bow change starts (one per bow change; see
    /// [`crate::bow_directions`]); empty in version-1 files.
    #[serde(default)]
    pub bow_directions: Vec<BowDirection>,
    /// Bow strokes with direction and string (schema 3; empty when the analysis has none,
    /// e.g. from the bow-change CNN or an older file).
    #[serde(default)]
    pub bow_strokes: Vec<BowStroke>,
    /// Beats in seconds.
    pub beats_s: Vec<f64>,
    /// Downbeats in seconds.
    pub downbeats_s: Vec<f64>,
    /// Tempo in bpm.
    pub tempo_bpm: f64,
    /// Beats per bar and subdivisions, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub meter: Option<Meter>,
    /// Arousal at 2 Hz.
    pub arousal: ArousalCurve,
}
