//! The whole chain: onset strength → onsets, tempo → beats → metre and downbeats.

use serde::{Deserialize, Serialize};

use pitch_track::Note;

use crate::dp::track_beats;
use crate::error::{BeatError, Result};
use crate::meter::{estimate_meter, Meter, MeterConfig};
use crate::onset::{Aggregate, OnsetConfig, OnsetStrength};
use crate::peaks::{onset_detect, PeakPick};
use crate::tempo::{estimate_tempo, TempoConfig};

/// Everything that defines a [`BeatTracker`]; the defaults are librosa's `beat_track`
/// (median-aggregated onset strength, prior at 120 bpm, tightness 100, trimming on).
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
    /// Drop weak leading and trailing beats.
    pub trim: bool,
    /// Metre detection.
    pub meter: MeterConfig,
}

impl Default for BeatConfig {
    fn default() -> Self {
        Self {
            onset: OnsetConfig::default(),
            beat_aggregate: Aggregate::Mean,
            tempo: TempoConfig::default(),
            tightness: 100.0,
            trim: true,
            meter: MeterConfig::default(),
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

/// A planned beat tracker.
#[derive(Debug)]
pub struct BeatTracker {
    cfg: BeatConfig,
    onset: OnsetStrength,
}

impl BeatTracker {
    /// Validates `cfg` and plans the spectrogram.
    pub fn new(cfg: BeatConfig) -> Result<Self> {
        if !(cfg.tightness.is_finite() && cfg.tightness > 0.0) {
            return Err(BeatError::InvalidConfig(format!(
                "tightness must be > 0, got {}",
                cfg.tightness
            )));
        }
        let t = &cfg.tempo;
        if !(t.start_bpm > 0.0 && t.std_bpm > 0.0 && t.ac_size_s > 0.0 && t.max_tempo_bpm > 0.0) {
            return Err(BeatError::InvalidConfig(
                "tempo start_bpm, std_bpm, ac_size_s and max_tempo_bpm must be > 0".into(),
            ));
        }
        let onset = OnsetConfig {
            with_median: cfg.onset.with_median || cfg.beat_aggregate == Aggregate::Median,
            ..cfg.onset.clone()
        };
        Ok(Self {
            onset: OnsetStrength::new(onset)?,
            cfg,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &BeatConfig {
        &self.cfg
    }

    /// Analyses `samples` (mono, at the configured rate). `notes` (from `pitch-track`) add
    /// evidence for the downbeats. Silence gives no onsets, no beats and tempo 0; empty or
    /// non-finite audio is an error.
    pub fn track(&self, samples: &[f32], notes: Option<&[Note]>) -> Result<BeatAnalysis> {
        let env = self.onset.compute(samples)?;
        let oc = &self.cfg.onset;
        let frame_s = env.hop_s;
        let onsets_s = onset_detect(
            &env.mean,
            &PeakPick::onset_defaults(oc.sample_rate_hz, oc.hop_length),
        )
        .into_iter()
        .map(|f| f as f64 * frame_s)
        .collect();
        let beat_env = env.get(self.cfg.beat_aggregate);
        let empty = |onsets_s| BeatAnalysis {
            tempo_bpm: 0.0,
            beats_s: Vec::new(),
            downbeats_s: Vec::new(),
            meter: Meter {
                beats_per_bar: 4,
                subdivisions: 2,
            },
            onsets_s,
        };
        if beat_env.iter().all(|&v| v == 0.0) {
            return Ok(empty(onsets_s));
        }
        let Some(bpm) = estimate_tempo(beat_env, oc.sample_rate_hz, oc.hop_length, &self.cfg.tempo)
        else {
            return Ok(empty(onsets_s));
        };
        let beats: Vec<f64> = track_beats(
            beat_env,
            bpm,
            1.0 / frame_s,
            self.cfg.tightness,
            self.cfg.trim,
        )
        .into_iter()
        .map(|f| f as f64 * frame_s)
        .collect();
        let meter = estimate_meter(&beats, &env, notes, bpm, &self.cfg.meter);
        Ok(BeatAnalysis {
            tempo_bpm: meter.tempo_bpm,
            beats_s: meter.beats_s,
            downbeats_s: meter.downbeats_s,
            meter: meter.meter,
            onsets_s,
        })
    }
}
