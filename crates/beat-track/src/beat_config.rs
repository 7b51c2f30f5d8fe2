//! What a [`crate::BeatTracker`] is configured with and what it returns.

use serde::{Deserialize, Serialize};

use crate::level::LevelConfig;
use crate::meter::Meter;
use crate::meter_config::MeterConfig;
use crate::onset::{Aggregate, OnsetConfig};
use crate::tempo::TempoConfig;

/// Everything that defines a [`crate::BeatTracker`]. Onset strength, tempogram, prior and the
/// dynamic programme are librosa's `beat_track` (prior at 120 bpm, tightness 100, trimming
/// on); the beat level is chosen among the tempogram's peaks ([`LevelConfig`]; `candidates`
/// 0 gives librosa's single tempo), and beats are reported [`BeatConfig::latency_s`] earlier
/// than the onset-strength frames they were tracked on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BeatConfig {
    /// Onset strength.
    pub onset: OnsetConfig,
    /// Aggregation used for tempo and beats (`onset_detect` always uses the mean).
    pub beat_aggregate: Aggregate,
    /// Tempo prior and window.
    pub tempo: TempoConfig,
    /// How strictly beats keep the period.
    pub tightness: f64,
    /// librosa's trimming: drop leading and trailing beats whose onset strength is below
    /// half the RMS of the beats' (off by default; see [`BeatConfig::keep_to_notes`]).
    pub trim: bool,
    /// Metre detection.
    pub meter: MeterConfig,
    /// Choice of the beat level among tempogram peaks.
    #[serde(default)]
    pub level: LevelConfig,
    /// How much later than the note onset the onset-strength peak of a beat comes, in
    /// seconds: the spectral flux peaks once the attack has built up. Beats are reported
    /// this much earlier than the frames they were tracked on (0 = librosa's frame times).
    #[serde(default = "default_latency_s")]
    pub latency_s: f64,
    /// Weight of note-start salience in the dynamic programme, in standard deviations of
    /// the onset strength per unit of salience (0 = onset strength alone, as librosa). A
    /// note adds `clamp(log₂(length in beats) + 2, 0, 3)` at its onset frame: nothing for
    /// a sixteenth, 2 for a quarter, 3 for a half note or longer. In a run of even notes
    /// every onset is as strong as the next and the onset strength alone cannot tell the
    /// beat from the off-beat; long notes tend to start on beats.
    #[serde(default = "default_note_salience")]
    pub note_salience: f64,
    /// Keep beats only where the music sounds: from the first note onset (less the beat
    /// tolerance) until half a beat before the last note ends. Used instead of librosa's
    /// trimming of weak beats ([`BeatConfig::trim`]), which also drops the beats of quiet
    /// openings and endings.
    #[serde(default = "default_keep_to_notes")]
    pub keep_to_notes: bool,
    /// Fewer detected onsets than this, and (with notes) fewer notes, and no beats nor a
    /// tempo are returned: a lone note's attack is not a pulse, and the dynamic programme
    /// would lay a tempo over it anyway.
    #[serde(default = "default_min_onsets")]
    pub min_onsets: usize,
}

fn default_min_onsets() -> usize {
    3
}

/// Chosen on corpus-fit among weights 0.5–4 and caps of 3–6 (see the crate README).
fn default_note_salience() -> f64 {
    1.0
}

fn default_keep_to_notes() -> bool {
    true
}

/// The median delay of tracked beats behind the labelled ones on the corpus's training
/// split was 41 ms (built-in synthesizer) and 48 ms (SoundFont).
fn default_latency_s() -> f64 {
    0.04
}

impl Default for BeatConfig {
    fn default() -> Self {
        Self {
            onset: OnsetConfig::default(),
            beat_aggregate: Aggregate::Mean,
            tempo: TempoConfig::default(),
            tightness: 100.0,
            trim: false,
            meter: MeterConfig::default(),
            level: LevelConfig::default(),
            latency_s: default_latency_s(),
            note_salience: default_note_salience(),
            keep_to_notes: default_keep_to_notes(),
            min_onsets: default_min_onsets(),
        }
    }
}

/// Onsets, tempo, beats, metre and downbeats of a recording.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BeatAnalysis {
    /// Tempo of the returned beats in bpm (0 when there are none).
    pub tempo_bpm: f64,
    /// Beat times in seconds.
    pub beats_s: Vec<f64>,
    /// Downbeat times in seconds.
    pub downbeats_s: Vec<f64>,
    /// The metre.
    pub meter: Meter,
    /// Onset times in seconds (`onset_detect`).
    pub onsets_s: Vec<f64>,
}
