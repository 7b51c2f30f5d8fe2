//! The weights of [`crate::meter`]'s beat-strength features and its compound-metre rule.

use serde::{Deserialize, Serialize};

/// Weights of the beat-strength features and the compound-metre rule.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeterConfig {
    /// Weight of the onset accent.
    pub accent_weight: f64,
    /// Weight of the loudness over the first half of the beat.
    pub level_weight: f64,
    /// Weight of the onset-free space after the beat.
    pub space_weight: f64,
    /// Weight of the note duration (when notes are given).
    pub duration_weight: f64,
    /// Weight of a pitch change on the beat (when notes are given).
    pub change_weight: f64,
    /// The readings "tracked beats are eighths" are tried only at or above this tempo.
    pub subdivision_min_bpm: f64,
    /// Extra BIC cost of those readings, in units of `ln n`.
    pub subdivision_penalty: f64,
    /// Tolerance for a note onset to count as on the beat, in seconds.
    pub note_tolerance_s: f64,
    /// Weight of a rest before the note starting on the beat (a phrase start).
    pub rest_weight: f64,
    /// Shortest rest that counts, in beats.
    pub min_rest_beats: f64,
    /// Weight of a bow change on the beat (when bow changes are given).
    #[serde(default)]
    pub bow_weight: f64,
}

impl Default for MeterConfig {
    /// The feature weights were found by `scripts/fit_meter.py` on the corpus's training
    /// and validation items (151): the onset-free space and the pitch change add nothing
    /// there once accent, loudness, note length and rests are counted, so they weigh 0.
    fn default() -> Self {
        Self {
            accent_weight: 1.0,
            level_weight: 0.0,
            space_weight: 0.0,
            duration_weight: 0.262,
            change_weight: 0.0,
            subdivision_min_bpm: 130.0,
            subdivision_penalty: 1.0,
            note_tolerance_s: 0.07,
            rest_weight: 0.5,
            min_rest_beats: 0.5,
            bow_weight: 1.0,
        }
    }
}
