//! [`Analysis`]: what a recording tells — f0, notes with fingering, bow changes, beats,
//! downbeats, tempo and arousal — in the `analysis.json` schema of ARCHITECTURE.md.

use serde::{Deserialize, Serialize};

use crate::arousal::ArousalCurve;
use crate::bowing::BowDirection;
use crate::meter::Meter;
use crate::note::Note;
use crate::stroke::BowStroke;

/// The `analysis.json` schema version this crate writes: 2 added `schema_version`,
/// `source`, `meter`, `bow_directions` and the notes' `velocity`; 3 added `bow_strokes`,
/// `tempo_bpm_per_beat` and `beat_confidence` (files without `schema_version` are version 1
/// and still read).
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
    /// Tempo in bpm at every beat of `beats_s` (one value per beat; empty in files before
    /// version 3). See [`tempo_per_beat`].
    #[serde(default)]
    pub tempo_bpm_per_beat: Vec<f64>,
    /// How strongly the recording supports the beats, 0–1 (near 0 for silence or noise,
    /// 1 for MIDI input); absent in files before version 3.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beat_confidence: Option<f32>,
    /// Arousal at 2 Hz.
    pub arousal: ArousalCurve,
}

/// Tempo (bpm) at every beat: 60 over the mean of the intervals to its neighbours, leaving
/// out intervals longer than twice the median interval (gaps); a beat with no usable
/// neighbour takes the median tempo.
///
/// ```
/// let t = performance::tempo_per_beat(&[0.0, 0.5, 1.0, 1.6, 10.0]);
/// assert_eq!(t.len(), 5);
/// // The 8.4 s gap is left out: the last beat takes the median interval (0.6 s).
/// assert!((t[1] - 120.0).abs() < 1e-9 && (t[4] - 100.0).abs() < 1e-9);
/// ```
pub fn tempo_per_beat(beats_s: &[f64]) -> Vec<f64> {
    let ibis: Vec<f64> = beats_s.windows(2).map(|w| w[1] - w[0]).collect();
    let mut sorted: Vec<f64> = ibis.iter().copied().filter(|d| *d > 0.0).collect();
    if sorted.is_empty() {
        return vec![0.0; beats_s.len()];
    }
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let usable = |d: f64| d > 0.0 && d <= 2.0 * median;
    (0..beats_s.len())
        .map(|i| {
            let near: Vec<f64> = [i.checked_sub(1), (i < ibis.len()).then_some(i)]
                .into_iter()
                .flatten()
                .map(|k| ibis[k])
                .filter(|d| usable(*d))
                .collect();
            let d = if near.is_empty() {
                median
            } else {
                near.iter().sum::<f64>() / near.len() as f64
            };
            60.0 / d
        })
        .collect()
}
