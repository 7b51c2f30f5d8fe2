//! The whole chain: onset strength → onsets, tempo → beats → metre and downbeats.

use rayon::prelude::*;

use performance::Note;

use crate::bar_features::BarEvidence;
use crate::beat_config::{BeatAnalysis, BeatConfig};
use crate::dp::track_beats_with;
use crate::error::{BeatError, Result};
use crate::level::{
    level_features, notes_from_onsets, tempogram_peaks, LevelCandidate, TempogramPeak,
};
use crate::meter::{estimate_meter, Meter};
use crate::onset::{Aggregate, OnsetConfig, OnsetStrength};
use crate::peaks::{onset_detect, PeakPick};
use crate::tempo::{bpm_of_lag, mean_tempogram_strided, tempo_from_tempogram, tempogram_window};

/// A tempo in bpm and the beats tracked at it, in seconds.
type TempoAndBeats = (f64, Vec<f64>);

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
        if !(cfg.note_salience.is_finite() && cfg.note_salience >= 0.0) {
            return Err(BeatError::InvalidConfig(format!(
                "note_salience must be ≥ 0, got {}",
                cfg.note_salience
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

    /// [`BeatTracker::track`] with bow changes as well as notes: a level whose beats fall on
    /// bow changes scores higher ([`crate::LevelWeights::bow_coverage`]), and a beat with a
    /// bow change is more likely a bar line ([`crate::MeterConfig::bow_weight`]).
    pub fn track_with(&self, samples: &[f32], evidence: BarEvidence<'_>) -> Result<BeatAnalysis> {
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
        let notes = evidence.notes.map_or(0, <[Note]>::len);
        if beat_env.iter().all(|&v| v == 0.0) || onsets_s.len().max(notes) < self.cfg.min_onsets {
            return Ok(empty(onsets_s));
        }
        let Some((bpm, beats)) = self
            .tempo_and_beats(beat_env, frame_s, &onsets_s, evidence)
            .filter(|(_, beats)| !beats.is_empty())
        else {
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
        self.level_candidates_with(samples, BarEvidence::notes(notes))
    }

    /// [`BeatTracker::level_candidates`] with bow changes as well as notes, as
    /// [`BeatTracker::track_with`] sees them.
    pub fn level_candidates_with(
        &self,
        samples: &[f32],
        evidence: BarEvidence<'_>,
    ) -> Result<Vec<LevelCandidate>> {
        let env = self.onset.compute(samples)?;
        let onsets_s = self.onsets_s(&env.mean, env.hop_s);
        let beat_env = env.get(self.cfg.beat_aggregate);
        Ok(self
            .candidates(beat_env, env.hop_s, &onsets_s, evidence)
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

    /// Beat frames at `bpm` as seconds, latency removed, tracked on the onset strength and
    /// the salience of `notes` (see [`BeatConfig::note_salience`]).
    fn beats_at(&self, beat_env: &[f32], frame_s: f64, bpm: f64, notes: &[Note]) -> Vec<f64> {
        let period_s = 60.0 / bpm;
        let salience = (self.cfg.note_salience > 0.0 && !notes.is_empty())
            .then(|| note_salience(notes, beat_env.len(), frame_s, period_s, &self.cfg));
        let beats: Vec<f64> = track_beats_with(
            beat_env,
            salience.as_deref(),
            bpm,
            1.0 / frame_s,
            self.cfg.tightness,
            self.cfg.trim,
        )
        .into_iter()
        .map(|f| (f as f64 * frame_s - self.cfg.latency_s).max(0.0))
        .collect();
        match sounding_span(notes) {
            Some((start_s, end_s)) if self.cfg.keep_to_notes => {
                let (from, to) = (start_s - self.cfg.level.tolerance_s, end_s - 0.5 * period_s);
                beats
                    .into_iter()
                    .filter(|&b| b >= from && b <= to)
                    .collect()
            }
            _ => beats,
        }
    }

    /// The candidates with four beats or more and, when there are none, the beats at
    /// librosa's tempo on the same tempogram (tracked and kept the same way).
    fn candidates(
        &self,
        beat_env: &[f32],
        frame_s: f64,
        onsets_s: &[f64],
        evidence: BarEvidence<'_>,
    ) -> Option<(Vec<LevelCandidate>, Option<TempoAndBeats>)> {
        let (oc, tc, lc) = (&self.cfg.onset, &self.cfg.tempo, &self.cfg.level);
        if beat_env.iter().all(|&v| v == 0.0) {
            return None;
        }
        let win_length = tempogram_window(oc.sample_rate_hz, oc.hop_length, tc)?;
        let tg = mean_tempogram_strided(beat_env, win_length, tc.frame_stride);
        let onsets: Vec<f64> = onsets_s.iter().map(|t| t - self.cfg.latency_s).collect();
        let stand_in;
        let notes = match evidence.notes.filter(|n| !n.is_empty()) {
            Some(n) => n,
            None => {
                stand_in = notes_from_onsets(&onsets);
                &stand_in
            }
        };
        let bow_changes_s = evidence.bow_changes_s.unwrap_or(&onsets);
        let bpm_of = |lag: usize| bpm_of_lag(lag, oc.sample_rate_hz, oc.hop_length);
        let candidates = tempogram_peaks(&tg, bpm_of, lc.min_bpm, tc.max_tempo_bpm, lc.candidates)
            // Each candidate's dynamic programme is independent: one per core.
            .into_par_iter()
            .filter_map(|lag| {
                let bpm = bpm_of(lag);
                let beats_s = self.beats_at(beat_env, frame_s, bpm, notes);
                (beats_s.len() >= 4).then(|| {
                    let peak = TempogramPeak {
                        value: tg[lag],
                        bpm,
                        start_bpm: tc.start_bpm,
                    };
                    let features = level_features(
                        &beats_s,
                        peak,
                        notes,
                        &onsets,
                        bow_changes_s,
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
            .collect::<Vec<_>>();
        let fallback = if candidates.is_empty() {
            tempo_from_tempogram(&tg, oc.sample_rate_hz, oc.hop_length, tc)
                .map(|bpm| (bpm, self.beats_at(beat_env, frame_s, bpm, notes)))
        } else {
            None
        };
        Some((candidates, fallback))
    }

    /// The tempo and beats: the best-scoring candidate, or librosa's tempo when no peak
    /// gives four beats.
    fn tempo_and_beats(
        &self,
        beat_env: &[f32],
        frame_s: f64,
        onsets_s: &[f64],
        evidence: BarEvidence<'_>,
    ) -> Option<TempoAndBeats> {
        let (candidates, fallback) = self.candidates(beat_env, frame_s, onsets_s, evidence)?;
        match candidates
            .into_iter()
            .reduce(|best, c| if c.score > best.score { c } else { best })
        {
            Some(best) => Some((best.tempo_bpm, best.beats_s)),
            None => fallback,
        }
    }
}

/// The salience of `notes` per onset-strength frame, weighted (see
/// [`BeatConfig::note_salience`]); a note counts at the frame where its onset-strength peak
/// comes, [`BeatConfig::latency_s`] after its onset.
fn note_salience(
    notes: &[Note],
    frames: usize,
    frame_s: f64,
    period_s: f64,
    cfg: &BeatConfig,
) -> Vec<f64> {
    let mut salience = vec![0.0; frames];
    for n in notes {
        let beats = (n.offset_s - n.onset_s) / period_s;
        let s = (beats.max(1e-3).log2() + 2.0).clamp(0.0, 3.0);
        let frame = ((n.onset_s + cfg.latency_s) / frame_s).round();
        if frame >= 0.0 && frame < frames as f64 {
            salience[frame as usize] += cfg.note_salience * s;
        }
    }
    salience
}

/// From the first note onset to the last note offset, in seconds (non-finite times are
/// ignored).
fn sounding_span(notes: &[Note]) -> Option<(f64, f64)> {
    let finite = |t: &f64| t.is_finite();
    let start = notes
        .iter()
        .map(|n| n.onset_s)
        .filter(finite)
        .min_by(f64::total_cmp)?;
    let end = notes
        .iter()
        .map(|n| n.offset_s)
        .filter(finite)
        .max_by(f64::total_cmp)?;
    Some((start, end))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn note(onset_s: f64, offset_s: f64) -> Note {
        Note::new(onset_s, offset_s, 69)
    }

    #[test]
    fn long_notes_are_more_salient_than_short_ones() {
        let cfg = BeatConfig::default();
        let frame_s = 0.01;
        // At 60 bpm: a sixteenth, an eighth, a quarter, a whole note.
        let notes = [
            note(0.0, 0.25),
            note(1.0, 1.5),
            note(2.0, 3.0),
            note(3.0, 7.0),
        ];
        let s = note_salience(&notes, 800, frame_s, 1.0, &cfg);
        let at = |t: f64| s[((t + cfg.latency_s) / frame_s).round() as usize];
        let w = cfg.note_salience;
        assert_eq!(
            [at(0.0), at(1.0), at(2.0), at(3.0)],
            [0.0, w, 2.0 * w, 3.0 * w]
        );
        assert_eq!(s.iter().filter(|&&v| v != 0.0).count(), 3);
        // Onsets outside the envelope or not finite are skipped, not a panic.
        let odd = [note(-1.0, 0.0), note(f64::NAN, 1.0), note(100.0, 101.0)];
        assert!(note_salience(&odd, 800, frame_s, 1.0, &cfg)
            .iter()
            .all(|&v| v == 0.0));
    }

    #[test]
    fn the_sounding_span_runs_from_the_first_onset_to_the_last_offset() {
        assert_eq!(
            sounding_span(&[note(1.0, 2.0), note(0.5, 0.8), note(3.0, 3.5)]),
            Some((0.5, 3.5))
        );
        assert_eq!(sounding_span(&[]), None);
        assert_eq!(
            sounding_span(&[note(1.0, f64::NAN), note(f64::NAN, 2.0)]),
            Some((1.0, 2.0))
        );
        assert_eq!(sounding_span(&[note(f64::NAN, f64::NAN)]), None);
    }

    #[test]
    fn negative_or_nan_salience_is_rejected() {
        for bad in [-1.0, f64::NAN, f64::INFINITY] {
            let cfg = BeatConfig {
                note_salience: bad,
                ..BeatConfig::default()
            };
            assert!(matches!(
                BeatTracker::new(cfg),
                Err(BeatError::InvalidConfig(_))
            ));
        }
    }
}
