//! The whole chain: onset strength → onsets, tempo → beats → metre and downbeats.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use pitch_track::Note;

use crate::bar_features::BarEvidence;
use crate::dp::track_beats;
use crate::error::{BeatError, Result};
use crate::level::{
    level_features, notes_from_onsets, tempogram_peaks, LevelCandidate, LevelConfig,
};
use crate::meter::{estimate_meter, Meter, MeterConfig};
use crate::onset::{Aggregate, OnsetConfig, OnsetStrength};
use crate::peaks::{onset_detect, PeakPick};
use crate::tempo::{
    bpm_of_lag, mean_tempogram_strided, tempo_from_tempogram, tempogram_window, TempoConfig,
};

/// Everything that defines a [`BeatTracker`]. Onset strength, tempogram, prior and the
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
    /// Drop weak leading and trailing beats.
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
            trim: true,
            meter: MeterConfig::default(),
            level: LevelConfig::default(),
            latency_s: default_latency_s(),
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
        if !(cfg.latency_s.is_finite() && cfg.latency_s >= 0.0) {
            return Err(BeatError::InvalidConfig(format!(
                "latency_s must be ≥ 0, got {}",
                cfg.latency_s
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

    /// Analyses `samples` (mono, at the configured rate). `notes` (from `pitch-track`) help
    /// choose the beat level and the downbeats. Silence gives no onsets, no beats and
    /// tempo 0; empty or non-finite audio is an error.
    pub fn track(&self, samples: &[f32], notes: Option<&[Note]>) -> Result<BeatAnalysis> {
        self.track_with(samples, BarEvidence::notes(notes))
    }

    /// [`BeatTracker::track`] with bow changes as well as notes: a beat with a bow change
    /// is more likely a bar line ([`MeterConfig::bow_weight`]).
    pub fn track_with(&self, samples: &[f32], evidence: BarEvidence<'_>) -> Result<BeatAnalysis> {
        let notes = evidence.notes;
        let env = self.onset.compute(samples)?;
        let frame_s = env.hop_s;
        let onsets_s = self.onsets_s(&env.mean, frame_s);
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
        let Some((bpm, beats)) = self.tempo_and_beats(beat_env, frame_s, &onsets_s, notes) else {
            return Ok(empty(onsets_s));
        };
        let meter = estimate_meter(&beats, &env, evidence, bpm, &self.cfg.meter);
        Ok(BeatAnalysis {
            tempo_bpm: meter.tempo_bpm,
            beats_s: meter.beats_s,
            downbeats_s: meter.downbeats_s,
            meter: meter.meter,
            onsets_s,
        })
    }

    /// Every beat level [`BeatTracker::track`] considered on `samples`, in the order of
    /// their tempogram peaks (highest first), each with its features and score: what to
    /// look at when the chosen tempo is not the one you expected.
    pub fn level_candidates(
        &self,
        samples: &[f32],
        notes: Option<&[Note]>,
    ) -> Result<Vec<LevelCandidate>> {
        let env = self.onset.compute(samples)?;
        let onsets_s = self.onsets_s(&env.mean, env.hop_s);
        let beat_env = env.get(self.cfg.beat_aggregate);
        Ok(self
            .candidates(beat_env, env.hop_s, &onsets_s, notes)
            .map(|(c, _)| c)
            .unwrap_or_default())
    }

    fn onsets_s(&self, mean_env: &[f32], frame_s: f64) -> Vec<f64> {
        let oc = &self.cfg.onset;
        onset_detect(
            mean_env,
            &PeakPick::onset_defaults(oc.sample_rate_hz, oc.hop_length),
        )
        .into_iter()
        .map(|f| f as f64 * frame_s)
        .collect()
    }

    /// Beat frames at `bpm` as seconds, latency removed.
    fn beats_at(&self, beat_env: &[f32], frame_s: f64, bpm: f64) -> Vec<f64> {
        track_beats(
            beat_env,
            bpm,
            1.0 / frame_s,
            self.cfg.tightness,
            self.cfg.trim,
        )
        .into_iter()
        .map(|f| (f as f64 * frame_s - self.cfg.latency_s).max(0.0))
        .collect()
    }

    /// The candidates with four beats or more, and librosa's tempo on the same tempogram.
    fn candidates(
        &self,
        beat_env: &[f32],
        frame_s: f64,
        onsets_s: &[f64],
        notes: Option<&[Note]>,
    ) -> Option<(Vec<LevelCandidate>, Option<f64>)> {
        let (oc, tc, lc) = (&self.cfg.onset, &self.cfg.tempo, &self.cfg.level);
        if beat_env.iter().all(|&v| v == 0.0) {
            return None;
        }
        let win_length = tempogram_window(oc.sample_rate_hz, oc.hop_length, tc)?;
        let tg = mean_tempogram_strided(beat_env, win_length, tc.frame_stride);
        let onsets: Vec<f64> = onsets_s.iter().map(|t| t - self.cfg.latency_s).collect();
        let stand_in;
        let notes = match notes.filter(|n| !n.is_empty()) {
            Some(n) => n,
            None => {
                stand_in = notes_from_onsets(&onsets);
                &stand_in
            }
        };
        let bpm_of = |lag: usize| bpm_of_lag(lag, oc.sample_rate_hz, oc.hop_length);
        let candidates = tempogram_peaks(&tg, bpm_of, lc.min_bpm, tc.max_tempo_bpm, lc.candidates)
            // Each candidate's dynamic programme is independent: one per core.
            .into_par_iter()
            .filter_map(|lag| {
                let bpm = bpm_of(lag);
                let beats_s = self.beats_at(beat_env, frame_s, bpm);
                (beats_s.len() >= 4).then(|| {
                    let features = level_features(
                        &beats_s,
                        tg[lag],
                        bpm,
                        tc.start_bpm,
                        notes,
                        &onsets,
                        lc.tolerance_s,
                    );
                    LevelCandidate {
                        tempo_bpm: bpm,
                        beats_s,
                        score: features.score(&lc.weights),
                        features,
                    }
                })
            })
            .collect();
        let librosa = tempo_from_tempogram(&tg, oc.sample_rate_hz, oc.hop_length, tc);
        Some((candidates, librosa))
    }

    /// The tempo and beats: the best-scoring candidate, or librosa's tempo when no peak
    /// gives four beats.
    fn tempo_and_beats(
        &self,
        beat_env: &[f32],
        frame_s: f64,
        onsets_s: &[f64],
        notes: Option<&[Note]>,
    ) -> Option<(f64, Vec<f64>)> {
        let (candidates, librosa) = self.candidates(beat_env, frame_s, onsets_s, notes)?;
        match candidates
            .into_iter()
            .reduce(|best, c| if c.score > best.score { c } else { best })
        {
            Some(best) => Some((best.tempo_bpm, best.beats_s)),
            None => librosa.map(|bpm| (bpm, self.beats_at(beat_env, frame_s, bpm))),
        }
    }
}
