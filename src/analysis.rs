//! `Analysis`: what the recording tells — f0, notes with fingering, bow changes, beats,
//! downbeats, tempo and arousal — in the `analysis.json` schema of ARCHITECTURE.md.

use serde::{Deserialize, Serialize};

/// Frame-wise fundamental frequency.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct F0Track {
    /// Seconds between frames.
    pub hop_s: f64,
    /// f0 in Hz per frame; 0 where unvoiced (JSON has no NaN).
    pub hz: Vec<f32>,
    /// Probability that each frame is voiced.
    pub voiced_prob: Vec<f32>,
}

impl F0Track {
    /// The same track at `fps` frames per second (e.g. 30 for the skeleton), resampled by
    /// `pitch_track::PitchTrack::resample_to_fps` (log-frequency interpolation between voiced
    /// frames, nearest frame across voicing changes).
    pub fn resampled_to_fps(&self, fps: f64) -> F0Track {
        let track = pitch_track::PitchTrack {
            hop_s: self.hop_s,
            f0_hz: self
                .hz
                .iter()
                .map(|&f| if f > 0.0 { f } else { f32::NAN })
                .collect(),
            voiced_prob: self.voiced_prob.clone(),
        }
        .resample_to_fps(fps);
        F0Track {
            hop_s: track.hop_s,
            hz: track
                .f0_hz
                .iter()
                .map(|&f| if f.is_finite() { f } else { 0.0 })
                .collect(),
            voiced_prob: track.voiced_prob,
        }
    }
}

/// A note with the place it is played at (absent when no place plays it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AnalyzedNote {
    /// Onset in seconds.
    pub onset_s: f64,
    /// Offset in seconds.
    pub offset_s: f64,
    /// MIDI pitch.
    pub midi: u8,
    /// String 1 (G) ..= 4 (E).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub string: Option<u8>,
    /// Position (0 = half position).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<u8>,
    /// Finger (0 = open string).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub finger: Option<u8>,
}

/// An arousal curve in [-1, 1] (DEAM convention).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArousalSeries {
    /// Values per second (2).
    pub rate_hz: f64,
    /// The values.
    pub values: Vec<f32>,
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
    pub notes: Vec<AnalyzedNote>,
    /// Bow changes in seconds.
    pub bow_changes_s: Vec<f64>,
    /// Beats in seconds.
    pub beats_s: Vec<f64>,
    /// Downbeats in seconds.
    pub downbeats_s: Vec<f64>,
    /// Tempo in bpm.
    pub tempo_bpm: f64,
    /// Arousal at 2 Hz.
    pub arousal: ArousalSeries,
}
