//! Choosing the beat level among the tempogram's peaks.
//!
//! librosa's `beat_track` takes the tempogram lag with the highest score after a log-normal
//! prior at 120 bpm. On solo violin music that choice is close to a coin toss between the
//! beat, twice the beat and 3/2 of it: the mean tempogram of a piece full of subdivisions is
//! nearly flat across those lags, so the prior decides. Here every strong tempogram peak is
//! tracked (the dynamic programme costs well under a millisecond per tempo) and the beat
//! sequences are compared on what a beat looks like in the music:
//!
//! * **tempogram** — `ln` of the mean tempogram at the candidate's lag;
//! * **prior** — librosa's log-normal prior, `−½ log₂(bpm / start_bpm)²`;
//! * **note coverage** — the share of beats with a note onset (from `pitch-track`) within
//!   [`LevelConfig::tolerance_s`]: a beat is where notes start;
//! * **onset coverage** — the same with the detected spectral-flux onsets;
//! * **note length** — the mean of `log₂` of the length, in beats, of the note starting on
//!   each beat (−3 where none starts): long notes begin on beats, not between them;
//! * **bow coverage** — the share of beats with a bow change (from `bowing-net`) within
//!   the tolerance: bow strokes, and so slurred groups, tend to start on beats.
//!
//! The candidate with the highest weighted sum wins. The weights ([`LevelWeights::default`])
//! were fitted by `scripts/fit_beat_level.py` on a 480-item synthetic corpus (see the crate
//! README). Without notes, the detected onsets stand in for them; without bow changes, the
//! detected onsets stand in for those (every note a new bow, as in détaché).

use serde::{Deserialize, Serialize};

use performance::Note;

/// Weights of the beat-level features (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LevelWeights {
    /// Weight of `ln` of the mean tempogram at the candidate's lag.
    pub tempogram: f64,
    /// Weight of the log-normal tempo prior.
    pub prior: f64,
    /// Weight of the share of beats on a note onset.
    pub note_coverage: f64,
    /// Weight of the share of beats on a detected onset.
    pub onset_coverage: f64,
    /// Weight of the mean log₂ length, in beats, of the notes starting on beats.
    pub note_length: f64,
    /// Weight of the share of beats on a bow change.
    #[serde(default)]
    pub bow_coverage: f64,
}

impl Default for LevelWeights {
    /// Fitted by `scripts/fit_beat_level.py --splits train,val,test --bow-changes DIR` on a
    /// 480-item corpus (`violin-skeleton corpus --minutes 240 --seed 777 --renderer mix`),
    /// with `DIR` holding `violin-skeleton analyze` outputs of its items.
    fn default() -> Self {
        Self {
            tempogram: 4.18,
            prior: 2.03,
            note_coverage: 2.06,
            onset_coverage: 3.26,
            note_length: 5.75,
            bow_coverage: 6.20,
        }
    }
}

/// How candidate beat levels are found and scored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LevelConfig {
    /// Track at most this many tempogram peaks (the highest ones); 0 disables the level
    /// choice and uses librosa's single tempo.
    pub candidates: usize,
    /// Slowest candidate tempo in bpm.
    pub min_bpm: f64,
    /// Tolerance for a beat to count as on a note or onset, in seconds.
    pub tolerance_s: f64,
    /// Feature weights.
    pub weights: LevelWeights,
}

impl Default for LevelConfig {
    fn default() -> Self {
        Self {
            candidates: 10,
            min_bpm: 25.0,
            tolerance_s: 0.07,
            weights: LevelWeights::default(),
        }
    }
}

/// The features of one candidate beat sequence (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LevelFeatures {
    /// `ln` of the mean tempogram at the lag.
    pub ln_tempogram: f64,
    /// `−½ log₂(bpm / start_bpm)²`.
    pub prior: f64,
    /// Share of beats with a note onset nearby.
    pub note_coverage: f64,
    /// Share of beats with a detected onset nearby.
    pub onset_coverage: f64,
    /// Mean log₂ length in beats of the note starting on each beat (−3 where none does).
    pub note_length: f64,
    /// Share of beats with a bow change nearby.
    #[serde(default)]
    pub bow_coverage: f64,
}

/// One tracked tempogram peak: its tempo, beats, features and score.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LevelCandidate {
    /// Tempo at the tempogram peak in bpm.
    pub tempo_bpm: f64,
    /// The beats tracked at that tempo, in seconds.
    pub beats_s: Vec<f64>,
    /// What the score is made of.
    pub features: LevelFeatures,
    /// The weighted sum of the features (higher wins).
    pub score: f64,
}

impl LevelFeatures {
    /// The weighted sum.
    pub fn score(&self, w: &LevelWeights) -> f64 {
        w.tempogram * self.ln_tempogram
            + w.prior * self.prior
            + w.note_coverage * self.note_coverage
            + w.onset_coverage * self.onset_coverage
            + w.note_length * self.note_length
            + w.bow_coverage * self.bow_coverage
    }
}

/// The lags of the `count` highest local maxima of `tempogram` whose tempo lies in
/// `[min_bpm, max_bpm)`, highest first; `bpm_of` converts a lag to bpm.
pub fn tempogram_peaks(
    tempogram: &[f64],
    bpm_of: impl Fn(usize) -> f64,
    min_bpm: f64,
    max_bpm: f64,
    count: usize,
) -> Vec<usize> {
    let n = tempogram.len();
    let mut peaks: Vec<usize> = (2..n.saturating_sub(1))
        .filter(|&l| {
            let bpm = bpm_of(l);
            bpm >= min_bpm
                && bpm < max_bpm
                && tempogram[l] > tempogram[l - 1]
                && tempogram[l] >= tempogram[l + 1]
                && tempogram[l] > 0.0
        })
        .collect();
    peaks.sort_by(|&a, &b| tempogram[b].total_cmp(&tempogram[a]));
    peaks.truncate(count);
    peaks
}

/// Share of `times` (sorted or not) with an element of the sorted `events` within `tol`.
fn coverage(times: &[f64], events: &[f64], tol: f64) -> f64 {
    if times.is_empty() || events.is_empty() {
        return 0.0;
    }
    let hits = times
        .iter()
        .filter(|&&t| has_event_near(events, t, tol))
        .count();
    hits as f64 / times.len() as f64
}

/// Whether one of the sorted `events` lies within `tol` of `t`.
pub(crate) fn has_event_near(events: &[f64], t: f64, tol: f64) -> bool {
    nearest(events, t).is_some_and(|k| (events[k] - t).abs() <= tol)
}

/// The median gap between consecutive sorted `times` (the upper one of an even count).
fn median_gap(times: &[f64]) -> Option<f64> {
    let mut gaps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    gaps.sort_by(f64::total_cmp);
    gaps.get(gaps.len() / 2).copied()
}

/// Index of the element of the sorted `events` nearest to `t`.
fn nearest(events: &[f64], t: f64) -> Option<usize> {
    let j = events.partition_point(|&e| e < t);
    match (j.checked_sub(1), (j < events.len()).then_some(j)) {
        (Some(a), Some(b)) => Some(if (events[a] - t).abs() <= (events[b] - t).abs() {
            a
        } else {
            b
        }),
        (a, b) => a.or(b),
    }
}

/// The features of `beats_s` (at least two beats) against `notes` (sorted by onset), the
/// sorted detected `onsets_s` and the sorted `bow_changes_s`. Without notes, pass the onsets
/// as notes lasting until the next onset; without bow changes, pass the onsets.
pub fn level_features(
    beats_s: &[f64],
    tempo: TempogramPeak,
    notes: &[Note],
    onsets_s: &[f64],
    bow_changes_s: &[f64],
    tolerance_s: f64,
) -> LevelFeatures {
    let TempogramPeak {
        value: tempogram_value,
        bpm,
        start_bpm,
    } = tempo;
    let ibi = median_gap(beats_s).unwrap_or(60.0 / bpm);
    let note_onsets: Vec<f64> = notes.iter().map(|n| n.onset_s).collect();
    let note_length = if beats_s.is_empty() {
        -3.0
    } else {
        beats_s
            .iter()
            .map(|&b| match nearest(&note_onsets, b) {
                Some(k) if (note_onsets[k] - b).abs() <= tolerance_s => {
                    ((notes[k].offset_s - notes[k].onset_s) / ibi)
                        .max(0.125)
                        .log2()
                }
                _ => -3.0,
            })
            .sum::<f64>()
            / beats_s.len() as f64
    };
    LevelFeatures {
        ln_tempogram: tempogram_value.max(1e-6).ln(),
        prior: -0.5 * (bpm / start_bpm).log2().powi(2),
        note_coverage: coverage(beats_s, &note_onsets, tolerance_s),
        onset_coverage: coverage(beats_s, onsets_s, tolerance_s),
        note_length,
        bow_coverage: coverage(beats_s, bow_changes_s, tolerance_s),
    }
}

/// A candidate's tempogram peak, for [`level_features`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TempogramPeak {
    /// The mean tempogram at the peak's lag.
    pub value: f64,
    /// The peak's tempo in bpm.
    pub bpm: f64,
    /// The centre of the tempo prior in bpm.
    pub start_bpm: f64,
}

/// Notes standing in for missing `pitch-track` notes: each onset lasts until the next one
/// (the last one for the median gap).
pub fn notes_from_onsets(onsets_s: &[f64]) -> Vec<Note> {
    let last_gap = median_gap(onsets_s).unwrap_or(0.5);
    onsets_s
        .iter()
        .enumerate()
        .map(|(i, &t)| Note::new(t, onsets_s.get(i + 1).copied().unwrap_or(t + last_gap), 0))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peaks_are_local_maxima_in_range_highest_first() {
        let tg = [1.0, 0.0, 0.5, 0.2, 0.9, 0.1, 0.3, 0.1, 0.0];
        let bpm_of = |l: usize| 600.0 / l as f64;
        assert_eq!(tempogram_peaks(&tg, bpm_of, 0.0, 1e9, 10), vec![4, 2, 6]);
        assert_eq!(tempogram_peaks(&tg, bpm_of, 0.0, 1e9, 1), vec![4]);
        // 600 / 6 = 100 bpm is the only peak in [90, 120) bpm.
        assert_eq!(tempogram_peaks(&tg, bpm_of, 90.0, 120.0, 10), vec![6]);
    }

    #[test]
    fn a_beat_on_every_note_start_scores_full_coverage() {
        let notes: Vec<Note> = (0..8)
            .map(|i| Note::new(0.5 * i as f64, 0.5 * i as f64 + 0.5, 69))
            .collect();
        let beats: Vec<f64> = (0..8).map(|i| 0.5 * i as f64 + 0.02).collect();
        let peak = |bpm| TempogramPeak {
            value: 1.0,
            bpm,
            start_bpm: 120.0,
        };
        let bows = [0.0, 2.0];
        let f = level_features(&beats, peak(120.0), &notes, &[], &bows, 0.07);
        assert_eq!(f.note_coverage, 1.0);
        assert_eq!(f.onset_coverage, 0.0);
        assert_eq!(f.bow_coverage, 0.25);
        assert!(f.note_length.abs() < 1e-12 && f.prior == 0.0 && f.ln_tempogram == 0.0);
        // Twice as fast: half the beats fall between notes, the notes last two beats.
        let fast: Vec<f64> = (0..16).map(|i| 0.25 * i as f64).collect();
        let g = level_features(&fast, peak(240.0), &notes, &[], &bows, 0.07);
        assert_eq!(g.bow_coverage, 0.125);
        assert_eq!(g.note_coverage, 0.5);
        assert!((g.note_length - (0.5 * 1.0 + 0.5 * -3.0)).abs() < 1e-12);
        assert!(f.score(&LevelWeights::default()) > g.score(&LevelWeights::default()));
    }

    #[test]
    fn onsets_stand_in_for_notes() {
        let notes = notes_from_onsets(&[1.0, 1.5, 2.5]);
        assert_eq!(notes.len(), 3);
        assert_eq!(notes[0].offset_s, 1.5);
        // The last note lasts the median gap (the upper one of an even count).
        assert_eq!(notes[2].offset_s, 2.5 + 1.0);
        assert!(notes_from_onsets(&[]).is_empty());
    }
}
