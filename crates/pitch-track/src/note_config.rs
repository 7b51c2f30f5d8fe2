//! [`NoteConfig`]: the parameters of note segmentation.

use serde::{Deserialize, Serialize};

use crate::novelty::NoveltyConfig;

/// Parameters of the segmentation (the method is described at [`crate::segment_notes`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NoteConfig {
    /// Shortest note kept, in seconds.
    pub min_note_s: f64,
    /// Median-filter length of the pitch, in seconds.
    pub smooth_s: f64,
    /// Extra distance beyond half a semitone before the quantised pitch changes.
    pub hysteresis_semitones: f32,
    /// Longest unvoiced gap bridged inside a note, in seconds.
    pub max_gap_s: f64,
    /// Minimum height of a novelty peak above its local mean, in dB.
    pub onset_delta_db: f32,
    /// Minimum height of a novelty peak, in dB.
    pub onset_floor_db: f32,
    /// Half width of the local mean and maximum windows for novelty peaks, in seconds.
    pub onset_window_s: f64,
    /// How far back the start of a run may move to an attack peak, in seconds.
    pub onset_snap_s: f64,
    /// The segmentation's latency, subtracted from every onset and offset, in seconds: the
    /// pitch path crosses the midpoint of a change after the change began (pYIN's frame
    /// spans ±23 ms, a slur glide takes 20–30 ms) and novelty peaks sit on the attack's rise.
    pub latency_s: f64,
    /// The novelty function.
    pub novelty: NoveltyConfig,
}

impl Default for NoteConfig {
    fn default() -> Self {
        Self {
            min_note_s: 0.07,
            smooth_s: 0.09,
            hysteresis_semitones: 0.2,
            max_gap_s: 0.05,
            onset_delta_db: 1.0,
            onset_floor_db: 2.0,
            onset_window_s: 0.05,
            onset_snap_s: 0.06,
            latency_s: 0.015,
            novelty: NoveltyConfig::default(),
        }
    }
}
