//! [`Performance`]: what is played when, and how — the input of motion synthesis.

use std::path::Path;

use fingering::{Fingering, FingeringError, FingeringPlanner};
use serde::{Deserialize, Serialize};

use crate::arousal::ArousalCurve;
use crate::error::{PerformanceError, PerformanceFileError};
use crate::note::Note;
use crate::stroke::BowStroke;
use crate::validate::{check_double_stops, check_notes, check_times};

/// The unvalidated fields of a [`Performance`] (also its JSON form).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PerformanceParts {
    /// Length of the performance, seconds.
    pub duration_s: f64,
    /// Notes in onset order.
    pub notes: Vec<Note>,
    /// Instants where the bow reverses, seconds, increasing.
    #[serde(default)]
    pub bow_changes_s: Vec<f64>,
    /// Beats, seconds, increasing.
    #[serde(default)]
    pub beats_s: Vec<f64>,
    /// Downbeats (first beat of each bar), seconds, increasing.
    #[serde(default)]
    pub downbeats_s: Vec<f64>,
    /// Arousal curve; `None` (or no values) is neutral.
    #[serde(default)]
    pub arousal: Option<ArousalCurve>,
    /// Per-note level in [0, 1] (one per note), when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dynamics: Option<Vec<f32>>,
    /// Bow strokes with direction and string, when known (from the stroke network or a
    /// score); starts strictly increasing, each ending at or after its start.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bow_strokes: Vec<BowStroke>,
    /// The other notes of double stops and chords: notes played together with a note of
    /// the line (`notes`), in onset order, each with its fingering when known. The bow
    /// crosses both strings while they sound; they are not trimmed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub double_stops: Vec<Note>,
}

/// What is played when, and how: the common language between analysis, the synthetic
/// corpus and motion synthesis (ARCHITECTURE.md). Always valid: built by
/// [`Performance::new`], [`Performance::builder`] or deserialisation, which all check it.
///
/// Rules checked on construction:
/// * `duration_s` is finite and positive; there is at least one note;
/// * every time is finite and inside `[0, duration_s]`; notes end after they start and have
///   MIDI pitches 0..=127;
/// * note onsets, bow changes, beats and downbeats are strictly increasing;
/// * **overlapping notes are trimmed**: the violin line is monophonic, so a note that
///   still sounds when the next one starts ends at that onset;
/// * arousal: a positive finite rate and values in [-1, 1] (out-of-range values are an
///   error, not clipped silently: they usually mean another scale such as DEAM's 1..9; use
///   [`ArousalCurve::clamped`] to clip on purpose);
/// * dynamics, when given: one level in [0, 1] per note;
/// * double stops (a second voice beside the line): times inside the performance, each
///   ending after it starts, in onset order.
///
/// The JSON form is [`PerformanceParts`]; fields that `analysis.json` adds (`f0`,
/// `tempo_bpm`, …) are ignored, so an analysis file reads as a performance.
///
/// ```
/// use performance::{ArousalCurve, Performance};
/// let perf = Performance::builder(2.0)
///     .note(0.0, 1.0, 67)
///     .note(1.0, 2.0, 71)
///     .bow_changes(vec![1.0])
///     .beats(vec![0.0, 0.5, 1.0, 1.5])
///     .downbeats(vec![0.0])
///     .arousal(ArousalCurve::deam(vec![0.0, 0.2, 0.4, 0.6]))
///     .build()?;
/// assert_eq!(perf.notes().len(), 2);
/// assert!(Performance::builder(0.0).note(0.0, 1.0, 60).build().is_err());
/// # Ok::<(), performance::PerformanceError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "PerformanceParts", into = "PerformanceParts")]
pub struct Performance {
    parts: PerformanceParts,
}

/// The longest performance, in seconds (24 hours).
pub const MAX_PERFORMANCE_S: f64 = 86_400.0;

impl Performance {
    /// Validates `parts` (see the type's rules) and trims overlapping notes.
    pub fn new(mut parts: PerformanceParts) -> Result<Performance, PerformanceError> {
        let d = parts.duration_s;
        // A day bounds the motion a performance asks for (2.6 M frames at 30 fps); a damaged
        // file saying 1e300 s must not reach an allocation (found by input-fuzz).
        if !(d.is_finite() && d > 0.0 && d <= MAX_PERFORMANCE_S) {
            return Err(PerformanceError::InvalidDuration { duration_s: d });
        }
        if parts.notes.is_empty() {
            return Err(PerformanceError::Empty);
        }
        check_notes(&mut parts.notes, d)?;
        check_double_stops(&parts.double_stops, d)?;
        check_times("bow_changes_s", &parts.bow_changes_s, d)?;
        check_times("beats_s", &parts.beats_s, d)?;
        check_times("downbeats_s", &parts.downbeats_s, d)?;
        if let Some(a) = &parts.arousal {
            if !(a.rate_hz.is_finite() && a.rate_hz > 0.0) {
                return Err(PerformanceError::InvalidArousalRate { rate_hz: a.rate_hz });
            }
            for (index, &value) in a.values.iter().enumerate() {
                if !value.is_finite() {
                    let value = f64::from(value);
                    return Err(PerformanceError::NonFinite {
                        field: "arousal.values",
                        index,
                        value,
                    });
                }
                if !(-1.0..=1.0).contains(&value) {
                    return Err(PerformanceError::ArousalOutOfRange { index, value });
                }
            }
        }
        let starts: Vec<f64> = parts.bow_strokes.iter().map(|s| s.start_s).collect();
        check_times("bow_strokes.start_s", &starts, d)?;
        let ends: Vec<f64> = parts.bow_strokes.iter().map(|s| s.end_s).collect();
        for (index, (&end, &start)) in ends.iter().zip(&starts).enumerate() {
            check_times("bow_strokes.end_s", std::slice::from_ref(&end), d).map_err(
                |e| match e {
                    PerformanceError::NonFinite { field, value, .. } => {
                        PerformanceError::NonFinite {
                            field,
                            index,
                            value,
                        }
                    }
                    PerformanceError::OutOfRange {
                        field,
                        value,
                        duration_s,
                        ..
                    } => PerformanceError::OutOfRange {
                        field,
                        index,
                        value,
                        duration_s,
                    },
                    other => other,
                },
            )?;
            if end < start {
                return Err(PerformanceError::Unsorted {
                    field: "bow_strokes.end_s",
                    index,
                    value: end,
                });
            }
        }
        if let Some(levels) = &parts.dynamics {
            if levels.len() != parts.notes.len() {
                return Err(PerformanceError::DynamicsLength {
                    expected: parts.notes.len(),
                    got: levels.len(),
                });
            }
            if let Some((index, &value)) = levels
                .iter()
                .enumerate()
                .find(|(_, v)| !(0.0..=1.0).contains(*v))
            {
                return Err(PerformanceError::DynamicsOutOfRange { index, value });
            }
        }
        Ok(Performance { parts })
    }

    /// A builder for a performance of `duration_s` seconds.
    pub fn builder(duration_s: f64) -> PerformanceBuilder {
        PerformanceBuilder {
            parts: PerformanceParts {
                duration_s,
                ..PerformanceParts::default()
            },
        }
    }

    /// Reads a performance (or an `analysis.json`) from a JSON file.
    pub fn read_json(path: impl AsRef<Path>) -> Result<Performance, PerformanceFileError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| PerformanceFileError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        serde_json::from_str(&text).map_err(|e| PerformanceFileError::Parse {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })
    }

    /// Bow strokes with direction and string (empty when unknown).
    pub fn bow_strokes(&self) -> &[BowStroke] {
        &self.parts.bow_strokes
    }

    /// Length, seconds.
    pub fn duration_s(&self) -> f64 {
        self.parts.duration_s
    }

    /// The notes, in onset order, not overlapping.
    pub fn notes(&self) -> &[Note] {
        &self.parts.notes
    }

    /// The other notes of double stops and chords, in onset order (empty for a single
    /// line).
    pub fn double_stops(&self) -> &[Note] {
        &self.parts.double_stops
    }

    /// Bow changes, seconds, strictly increasing.
    pub fn bow_changes_s(&self) -> &[f64] {
        &self.parts.bow_changes_s
    }

    /// Beats, seconds, strictly increasing.
    pub fn beats_s(&self) -> &[f64] {
        &self.parts.beats_s
    }

    /// Downbeats, seconds, strictly increasing.
    pub fn downbeats_s(&self) -> &[f64] {
        &self.parts.downbeats_s
    }

    /// The arousal curve, when there is one with at least one value.
    pub fn arousal(&self) -> Option<&ArousalCurve> {
        self.parts.arousal.as_ref().filter(|a| !a.values.is_empty())
    }

    /// Per-note levels in [0, 1], when known.
    pub fn dynamics(&self) -> Option<&[f32]> {
        self.parts.dynamics.as_deref()
    }

    /// The validated fields.
    pub fn parts(&self) -> &PerformanceParts {
        &self.parts
    }

    /// Number of frames at `fps` that cover the duration: `ceil(duration_s · fps)`.
    pub fn frame_count(&self, fps: f64) -> usize {
        ((self.parts.duration_s * fps) - 1e-9).ceil().max(1.0) as usize
    }

    /// `true` when every note has a fingering.
    pub fn is_fingered(&self) -> bool {
        self.parts.notes.iter().all(|n| n.fingering.is_some())
    }

    /// The same performance with every note that has no fingering given one by `planner`
    /// (notes that already have one keep it). The planner sees the whole melody, so the
    /// filled notes are planned in context.
    ///
    /// ```
    /// use performance::Performance;
    /// use fingering::OptimalPlanner;
    /// let perf = Performance::builder(1.0).note(0.0, 0.5, 55).note(0.5, 1.0, 76).build()?;
    /// let fingered = perf.with_fingering(&OptimalPlanner::default())?;
    /// assert!(fingered.is_fingered());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_fingering<P: FingeringPlanner + ?Sized>(
        &self,
        planner: &P,
    ) -> Result<Performance, FingeringError> {
        let midi: Vec<u8> = self.parts.notes.iter().map(|n| n.midi).collect();
        let plan = planner.plan(&midi)?;
        let mut out = self.clone();
        for (note, f) in out.parts.notes.iter_mut().zip(plan) {
            note.fingering.get_or_insert(f);
        }
        Ok(out)
    }
}

impl TryFrom<PerformanceParts> for Performance {
    type Error = PerformanceError;
    fn try_from(parts: PerformanceParts) -> Result<Performance, PerformanceError> {
        Performance::new(parts)
    }
}

impl From<Performance> for PerformanceParts {
    fn from(p: Performance) -> PerformanceParts {
        p.parts
    }
}

/// Builds a [`Performance`] field by field; [`PerformanceBuilder::build`] validates.
#[derive(Debug, Clone)]
pub struct PerformanceBuilder {
    parts: PerformanceParts,
}

impl PerformanceBuilder {
    /// Adds a note without fingering.
    pub fn note(mut self, onset_s: f64, offset_s: f64, midi: u8) -> Self {
        self.parts.notes.push(Note::new(onset_s, offset_s, midi));
        self
    }

    /// Adds a note with its fingering.
    pub fn fingered_note(mut self, onset_s: f64, offset_s: f64, midi: u8, f: Fingering) -> Self {
        self.parts.notes.push(Note {
            fingering: Some(f),
            ..Note::new(onset_s, offset_s, midi)
        });
        self
    }

    /// Replaces the notes.
    pub fn notes(mut self, notes: Vec<Note>) -> Self {
        self.parts.notes = notes;
        self
    }

    /// Sets the bow changes, seconds.
    pub fn bow_changes(mut self, times_s: Vec<f64>) -> Self {
        self.parts.bow_changes_s = times_s;
        self
    }

    /// Sets the bow strokes (direction and string).
    pub fn bow_strokes(mut self, strokes: Vec<BowStroke>) -> Self {
        self.parts.bow_strokes = strokes;
        self
    }

    /// Sets the beats, seconds.
    pub fn beats(mut self, times_s: Vec<f64>) -> Self {
        self.parts.beats_s = times_s;
        self
    }

    /// Sets the downbeats, seconds.
    pub fn downbeats(mut self, times_s: Vec<f64>) -> Self {
        self.parts.downbeats_s = times_s;
        self
    }

    /// Sets the arousal curve.
    pub fn arousal(mut self, curve: ArousalCurve) -> Self {
        self.parts.arousal = Some(curve);
        self
    }

    /// Sets the per-note levels.
    pub fn dynamics(mut self, levels: Vec<f32>) -> Self {
        self.parts.dynamics = Some(levels);
        self
    }

    /// Sets the other notes of double stops and chords (onset order).
    pub fn double_stops(mut self, notes: Vec<Note>) -> Self {
        self.parts.double_stops = notes;
        self
    }

    /// Validates and builds.
    pub fn build(self) -> Result<Performance, PerformanceError> {
        Performance::new(self.parts)
    }
}
