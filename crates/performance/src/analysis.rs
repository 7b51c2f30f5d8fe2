//! [`Analysis`]: what a recording tells — f0, notes with fingering, bow changes, beats,
//! downbeats, tempo and arousal — in the `analysis.json` schema of ARCHITECTURE.md.

use serde::{Deserialize, Serialize};

use crate::arousal::ArousalCurve;
use crate::note::Note;

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

/// Everything the analysis found in a recording.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Analysis {
    /// Length of the recording in seconds.
    pub duration_s: f64,
    /// Sample rate of the input in Hz (the analysis runs at 22 050 Hz).
    pub sample_rate: u32,
    /// Fundamental frequency.
    pub f0: F0Track,
    /// Notes, in time order.
    pub notes: Vec<Note>,
    /// Bow changes in seconds.
    pub bow_changes_s: Vec<f64>,
    /// Beats in seconds.
    pub beats_s: Vec<f64>,
    /// Downbeats in seconds.
    pub downbeats_s: Vec<f64>,
    /// Tempo in bpm.
    pub tempo_bpm: f64,
    /// Arousal at 2 Hz.
    pub arousal: ArousalCurve,
}
