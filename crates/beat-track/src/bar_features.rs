//! The bar-level evidence of every tracked beat that [`crate::meter`] weighs.

use serde::{Deserialize, Serialize};

use performance::Note;

use crate::level::has_event_near;
use crate::meter_config::MeterConfig;
use crate::onset::OnsetEnvelope;

/// What, besides the audio, tells where bars begin: notes from `pitch-track` and bow
/// changes (e.g. from `bowing-net`; phrases and bars tend to start with a new bow).
///
/// ```
/// use beat_track::BarEvidence;
/// let bows = [0.5, 1.0, 2.0];
/// let evidence = BarEvidence { bow_changes_s: Some(&bows), ..BarEvidence::default() };
/// assert!(evidence.notes.is_none());
/// ```
#[derive(Debug, Clone, Copy, Default)]
pub struct BarEvidence<'a> {
    /// Notes, sorted by onset.
    pub notes: Option<&'a [Note]>,
    /// Bow-change times in seconds, sorted.
    pub bow_changes_s: Option<&'a [f64]>,
}

impl<'a> BarEvidence<'a> {
    /// Evidence from notes alone.
    pub fn notes(notes: Option<&'a [Note]>) -> Self {
        Self {
            notes,
            bow_changes_s: None,
        }
    }
}

/// The raw features of every beat (one value per beat in each vector; see [`crate::meter`]).
/// The note features are empty when no notes were given, `bow` when no bow changes were.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BeatFeatures {
    /// `ln(1 + peak onset strength)` within ±50 ms of the beat.
    pub accent: Vec<f64>,
    /// Minus `ln(1 + mean onset strength)` from 15 % to 85 % of the way to the next beat.
    pub space: Vec<f64>,
    /// Mean loudness (dB) over the first half of the beat.
    pub level: Vec<f64>,
    /// `log₂` of the length in beats of the note starting on the beat (≥ 1/8; −1 when a note
    /// is held through the beat, 0 when none sounds).
    pub duration: Vec<f64>,
    /// 1 when the note starting on the beat has a new pitch.
    pub change: Vec<f64>,
    /// 1 when the note starting on the beat follows a rest of at least
    /// [`MeterConfig::min_rest_beats`].
    pub rest: Vec<f64>,
    /// 1 when a bow change lies within [`MeterConfig::note_tolerance_s`] of the beat.
    pub bow: Vec<f64>,
}

impl BeatFeatures {
    /// The features of `beats_s` from the onset curves of `onsets` and the `evidence`.
    pub fn new(
        beats_s: &[f64],
        onsets: &OnsetEnvelope,
        evidence: BarEvidence<'_>,
        cfg: &MeterConfig,
    ) -> Self {
        let notes = evidence.notes;
        let (envelope, hop_s) = (&onsets.mean[..], onsets.hop_s);
        let n = beats_s.len();
        let frame =
            |t: f64| ((t / hop_s).round().max(0.0) as usize).min(envelope.len().saturating_sub(1));
        let ibi = |i: usize| {
            if i + 1 < n {
                beats_s[i + 1] - beats_s[i]
            } else {
                beats_s[i] - beats_s[i - 1]
            }
        };
        let reach = ((0.05 / hop_s).round() as usize).max(1);
        let mut accent = Vec::with_capacity(n);
        let mut space = Vec::with_capacity(n);
        let mut level = Vec::with_capacity(n);
        for (i, &b) in beats_s.iter().enumerate() {
            if envelope.is_empty() || onsets.loudness_db.len() != envelope.len() {
                accent.push(0.0);
                space.push(0.0);
                level.push(0.0);
                continue;
            }
            let c = frame(b);
            let peak = envelope[c.saturating_sub(reach)..(c + reach + 1).min(envelope.len())]
                .iter()
                .copied()
                .fold(0.0f32, f32::max);
            accent.push(f64::from(peak).ln_1p());
            let (lo, hi) = (frame(b + 0.15 * ibi(i)), frame(b + 0.85 * ibi(i)));
            let inside = &envelope[lo..hi.max(lo + 1).min(envelope.len())];
            let mean =
                inside.iter().map(|&v| f64::from(v)).sum::<f64>() / inside.len().max(1) as f64;
            space.push(-mean.ln_1p());
            let (lo, hi) = (frame(b + 0.05 * ibi(i)), frame(b + 0.5 * ibi(i)));
            let first_half = &onsets.loudness_db[lo..hi.max(lo + 1).min(envelope.len())];
            level.push(
                first_half.iter().map(|&v| f64::from(v)).sum::<f64>()
                    / first_half.len().max(1) as f64,
            );
        }
        let mut duration = Vec::new();
        let mut change = Vec::new();
        let mut rest = Vec::new();
        if let Some(notes) = notes.filter(|n| !n.is_empty()) {
            for (i, &b) in beats_s.iter().enumerate() {
                let starting = notes
                    .iter()
                    .enumerate()
                    .filter(|(_, x)| (x.onset_s - b).abs() <= cfg.note_tolerance_s)
                    .min_by(|a, c| (a.1.onset_s - b).abs().total_cmp(&(c.1.onset_s - b).abs()));
                match starting {
                    Some((k, note)) => {
                        duration.push(((note.offset_s - note.onset_s) / ibi(i)).max(0.125).log2());
                        let changed = k == 0 || notes[k - 1].midi != note.midi;
                        change.push(if changed { 1.0 } else { 0.0 });
                        let gap = if k == 0 {
                            f64::INFINITY
                        } else {
                            note.onset_s - notes[k - 1].offset_s
                        };
                        rest.push(if gap >= cfg.min_rest_beats * ibi(i) {
                            1.0
                        } else {
                            0.0
                        });
                    }
                    None => {
                        let held = notes.iter().any(|x| x.onset_s < b && x.offset_s > b);
                        duration.push(if held { -1.0 } else { 0.0 });
                        change.push(0.0);
                        rest.push(0.0);
                    }
                }
            }
        }
        let bow = match evidence.bow_changes_s.filter(|b| !b.is_empty()) {
            Some(bows) => beats_s
                .iter()
                .map(|&b| f64::from(u8::from(has_event_near(bows, b, cfg.note_tolerance_s))))
                .collect(),
            None => Vec::new(),
        };
        BeatFeatures {
            accent,
            space,
            level,
            duration,
            change,
            rest,
            bow,
        }
    }

    /// The weighted sum of the z-scored features of every beat (a constant or missing feature
    /// adds nothing).
    pub fn strength(&self, cfg: &MeterConfig) -> Vec<f64> {
        let mut strength = vec![0.0; self.accent.len()];
        add_scaled(&mut strength, &self.accent, cfg.accent_weight);
        add_scaled(&mut strength, &self.space, cfg.space_weight);
        add_scaled(&mut strength, &self.level, cfg.level_weight);
        add_scaled(&mut strength, &self.duration, cfg.duration_weight);
        add_scaled(&mut strength, &self.change, cfg.change_weight);
        add_scaled(&mut strength, &self.rest, cfg.rest_weight);
        add_scaled(&mut strength, &self.bow, cfg.bow_weight);
        strength
    }
}

/// `acc += weight · zscore(feature)` (a constant feature, or one of another length, adds
/// nothing).
fn add_scaled(acc: &mut [f64], feature: &[f64], weight: f64) {
    if feature.len() != acc.len() || feature.is_empty() {
        return;
    }
    let n = feature.len() as f64;
    let mean = feature.iter().sum::<f64>() / n;
    let sd = (feature.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
    if sd > 1e-12 {
        for (a, v) in acc.iter_mut().zip(feature) {
            *a += weight * (v - mean) / sd;
        }
    }
}
