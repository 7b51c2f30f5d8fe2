//! Metre and downbeats from bar-level evidence.
//!
//! Every tracked beat gets a *strength*: a weighted sum of z-scored features
//! * **accent** — the log onset strength at the beat (±50 ms) and the **level** (mean mel
//!   dB) over the first half of the beat: downbeats are played louder;
//! * **space** — the absence of onsets inside the following beat (a long note starts on a
//!   strong beat), measured on the onset curve;
//! * with notes from `pitch-track`: **duration** — log₂ of the length, in beats, of the note
//!   starting on the beat (−1 when a note is held through the beat), **change** — a new
//!   pitch starts on the beat (harmony moves at bar lines), and **rest** — the note starting
//!   on the beat follows a rest of at least [`MeterConfig::min_rest_beats`] (phrases start
//!   after rests, and at bar lines);
//! * with bow changes (e.g. from `bowing-net`): **bow** — a bow change on the beat (phrases,
//!   and so bars, start with a new bow).
//!
//! The default weights were fitted by `scripts/fit_meter.py` on a 480-item synthetic
//! corpus; level, space and change weigh 0 there (see the crate README).
//!
//! Each *hypothesis* labels every tracked beat as a downbeat, a beat or a subdivision:
//! * the tracked beats are the beats, `M` ∈ {2, 3, 4} per bar, phase `φ`
//!   (labels: downbeat / beat);
//! * the tracked beats are eighths of a simple metre (a tracker locked on double tempo):
//!   every second one is a beat, `M` ∈ {2, 3, 4} beats per bar (downbeat / beat / eighth);
//! * the tracked beats are eighths of 6/8: every third one is a beat, two beats per bar.
//!
//! The last two are tried only when the tracked tempo is at least
//! [`MeterConfig::subdivision_min_bpm`]. For each hypothesis the strengths are fitted by the
//! mean of each label (one-way ANOVA) and scored by the Bayesian information criterion
//! `n ln(RSS / n) + k ln n` (k = number of labels, plus [`MeterConfig::subdivision_penalty`]
//! for the finer-level readings); the lowest wins. A wrong bar length or phase puts strong
//! and weak beats under one label, which raises the residual; extra labels must pay for
//! themselves, and a hypothesis whose label means are not ordered downbeat ≥ beat ≥
//! subdivision is not considered. The winner gives the downbeats, the beats (every second or third tracked
//! beat for the finer-level readings) and the tempo at that level.

pub use performance::Meter;
use serde::{Deserialize, Serialize};

use crate::bar_features::{BarEvidence, BeatFeatures};
pub use crate::meter_config::MeterConfig;
use crate::onset::OnsetEnvelope;

/// The result of [`estimate_meter`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeterEstimate {
    /// The metre.
    pub meter: Meter,
    /// Beat times in seconds (every third input beat for a compound metre).
    pub beats_s: Vec<f64>,
    /// Downbeat times in seconds.
    pub downbeats_s: Vec<f64>,
    /// Beats per minute at the returned beat level.
    pub tempo_bpm: f64,
    /// Minus the winning BIC (higher is better; 0 when there were too few beats).
    pub confidence: f64,
}

/// Chooses the metre and the downbeats of `beats_s` from the onset curves of `envelope`
/// (the mean-aggregated onset strength and the loudness) and the optional notes and bow
/// changes of `evidence`.
/// With fewer than four beats the metre defaults to 4/4 and the first beat is the downbeat.
pub fn estimate_meter(
    beats_s: &[f64],
    envelope: &OnsetEnvelope,
    evidence: BarEvidence<'_>,
    tempo_bpm: f64,
    cfg: &MeterConfig,
) -> MeterEstimate {
    let hop_s = envelope.hop_s;
    let fallback = || MeterEstimate {
        meter: Meter {
            beats_per_bar: 4,
            subdivisions: 2,
        },
        beats_s: beats_s.to_vec(),
        downbeats_s: beats_s.first().copied().into_iter().collect(),
        tempo_bpm,
        confidence: 0.0,
    };
    if beats_s.len() < 4 || hop_s <= 0.0 {
        return fallback();
    }
    let strength = BeatFeatures::new(beats_s, envelope, evidence, cfg).strength(cfg);
    let n = strength.len();
    let ln_n = (n as f64).ln();
    // (beats per bar at the beat level, tracked beats per beat, phase of the first downbeat)
    let mut hypotheses: Vec<(usize, usize, usize)> = Vec::new();
    for m in [4usize, 3, 2] {
        hypotheses.extend((0..m).map(|phase| (m, 1, phase)));
    }
    if tempo_bpm >= cfg.subdivision_min_bpm {
        for m in [4usize, 3, 2] {
            hypotheses.extend((0..2 * m).map(|phase| (m, 2, phase)));
        }
        hypotheses.extend((0..6).map(|phase| (2, 3, phase)));
    }
    let mut best: Option<((usize, usize, usize), f64)> = None;
    for &(m, sub, phase) in &hypotheses {
        let period = m * sub;
        if n < 2 * period {
            continue;
        }
        let label = |i: usize| {
            let pos = (i + period - phase % period) % period;
            if pos == 0 {
                0
            } else if pos.is_multiple_of(sub) {
                1
            } else {
                2
            }
        };
        let labels = if sub == 1 { 2.0 } else { 3.0 };
        let (rss, means) = fit(&strength, label);
        // Accents are hierarchical: downbeats above beats above subdivisions.
        if means[0] < means[1] || (sub > 1 && means[1] < means[2]) {
            continue;
        }
        let rss = rss.max(1e-12 * n as f64);
        let mut bic = n as f64 * (rss / n as f64).ln() + labels * ln_n;
        if sub > 1 {
            bic += cfg.subdivision_penalty * ln_n;
        }
        if best.is_none_or(|(_, b)| bic < b) {
            best = Some(((m, sub, phase), bic));
        }
    }
    let Some(((m, sub, phase), bic)) = best else {
        return fallback();
    };
    let period = m * sub;
    let downbeats_s: Vec<f64> = beats_s
        .iter()
        .skip(phase % period)
        .step_by(period)
        .copied()
        .collect();
    MeterEstimate {
        meter: Meter {
            beats_per_bar: m as u8,
            subdivisions: if sub == 3 { 3 } else { 2 },
        },
        beats_s: beats_s
            .iter()
            .skip(phase % sub)
            .step_by(sub)
            .copied()
            .collect(),
        downbeats_s,
        tempo_bpm: tempo_bpm / sub as f64,
        confidence: -bic,
    }
}

/// Residual sum of squares of `strength` around the mean of each label (0, 1, 2), and the
/// means.
fn fit(strength: &[f64], label: impl Fn(usize) -> usize) -> (f64, [f64; 3]) {
    let mut sum = [0.0f64; 3];
    let mut count = [0usize; 3];
    for (i, &s) in strength.iter().enumerate() {
        sum[label(i)] += s;
        count[label(i)] += 1;
    }
    let mean = [0, 1, 2].map(|g| sum[g] / count[g].max(1) as f64);
    let rss = strength
        .iter()
        .enumerate()
        .map(|(i, &s)| (s - mean[label(i)]).powi(2))
        .sum();
    (rss, mean)
}

#[cfg(test)]
mod tests {
    use super::*;
    use performance::Note;

    fn accents(m: usize, n: usize, offset: usize) -> (Vec<f64>, OnsetEnvelope) {
        let hop_s = 0.01;
        let beats: Vec<f64> = (0..n).map(|i| 0.5 + 0.5 * i as f64).collect();
        let mut env = vec![0.0f32; 1 + (0.5 + 0.5 * n as f64 / hop_s) as usize + 100];
        for (i, b) in beats.iter().enumerate() {
            let k = (b / hop_s).round() as usize;
            env[k] = if i % m == offset { 3.0 } else { 1.0 } + 0.1 * (i % 5) as f32;
        }
        let loudness_db = vec![0.0; env.len()];
        let median = env.clone();
        (
            beats,
            OnsetEnvelope {
                hop_s,
                mean: env,
                median,
                loudness_db,
            },
        )
    }

    #[test]
    fn finds_bar_length_and_phase_from_accents() {
        for (m, offset) in [(4, 1), (3, 2), (2, 0)] {
            let (beats, env) = accents(m, 48, offset);
            let est = estimate_meter(
                &beats,
                &env,
                BarEvidence::default(),
                120.0,
                &MeterConfig::default(),
            );
            assert_eq!(est.meter.beats_per_bar as usize, m);
            assert!((est.downbeats_s[0] - beats[offset]).abs() < 1e-9);
        }
    }

    /// Flat onset curves (3000 frames of 10 ms) and 48 beats every 0.5 s from 0.5 s.
    fn flat_curves_and_beats() -> (OnsetEnvelope, Vec<f64>) {
        let flat = OnsetEnvelope {
            hop_s: 0.01,
            mean: vec![1.0; 3000],
            median: vec![1.0; 3000],
            loudness_db: vec![0.0; 3000],
        };
        (flat, (0..48).map(|i| 0.5 + 0.5 * i as f64).collect())
    }

    #[test]
    fn rests_before_notes_mark_phrase_starts() {
        // Flat onset curves; a note on every beat, and a 0.3 s rest after the notes on beats
        // 1, 4, 7, …: the notes on beats 2, 5, 8, … start phrases. The short notes make
        // beats 1, 4, … weak, which alone cannot tell phase 2 from phase 0.
        let (flat, beats) = flat_curves_and_beats();
        let notes: Vec<Note> = beats
            .iter()
            .enumerate()
            .map(|(i, &b)| Note::new(b, b + if i % 3 == 1 { 0.2 } else { 0.5 }, 69))
            .collect();
        let est = estimate_meter(
            &beats,
            &flat,
            BarEvidence::notes(Some(&notes)),
            120.0,
            &MeterConfig::default(),
        );
        assert_eq!(est.meter.beats_per_bar, 3);
        assert!(
            (est.downbeats_s[0] - beats[2]).abs() < 1e-9,
            "{:?}",
            est.downbeats_s
        );
        let without = MeterConfig {
            rest_weight: 0.0,
            ..MeterConfig::default()
        };
        let est = estimate_meter(
            &beats,
            &flat,
            BarEvidence::notes(Some(&notes)),
            120.0,
            &without,
        );
        assert!((est.downbeats_s[0] - beats[2]).abs() > 1e-9);
    }

    #[test]
    fn bow_changes_mark_bar_lines() {
        // Flat onset curves and no notes: only the bow changes, on beats 1, 4, 7, … (and on
        // a few others, as a real bow changes within bars too), tell the bar.
        let (flat, beats) = flat_curves_and_beats();
        let bows: Vec<f64> = beats
            .iter()
            .enumerate()
            .filter(|(i, _)| i % 3 == 1 || i % 7 == 0)
            .map(|(_, &b)| b + 0.02)
            .collect();
        let evidence = BarEvidence {
            notes: None,
            bow_changes_s: Some(&bows),
        };
        let est = estimate_meter(&beats, &flat, evidence, 120.0, &MeterConfig::default());
        assert_eq!(est.meter.beats_per_bar, 3);
        assert!(
            (est.downbeats_s[0] - beats[1]).abs() < 1e-9,
            "{:?}",
            est.downbeats_s
        );
        // Weighted 0, the bow changes say nothing: the first beat stays the downbeat.
        let deaf = MeterConfig {
            bow_weight: 0.0,
            ..MeterConfig::default()
        };
        let est = estimate_meter(&beats, &flat, evidence, 120.0, &deaf);
        assert_eq!(est.downbeats_s[0], beats[0]);
    }

    #[test]
    fn too_few_beats_fall_back_to_the_first_beat() {
        let flat = OnsetEnvelope {
            hop_s: 0.01,
            mean: vec![0.0; 300],
            median: vec![0.0; 300],
            loudness_db: vec![0.0; 300],
        };
        let est = estimate_meter(
            &[1.0, 1.5],
            &flat,
            BarEvidence::default(),
            120.0,
            &MeterConfig::default(),
        );
        assert_eq!(est.downbeats_s, vec![1.0]);
        let none = estimate_meter(
            &[],
            &flat,
            BarEvidence::default(),
            0.0,
            &MeterConfig::default(),
        );
        assert!(none.downbeats_s.is_empty());
    }
}
