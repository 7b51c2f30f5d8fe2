//! The analysis of a MIDI file, in the same `analysis.json` schema as a recording's.

use std::path::Path;

use performance::midi::{score_from_midi_file, timeline_from_score, MidiScore};
use performance::{
    arousal_proxy_of_spans, bow_directions, Analysis, ArousalCurve, F0Track, Note, Performance,
    ANALYSIS_SCHEMA_VERSION,
};

use crate::error::Result;
use crate::pipeline::Pipeline;

/// The f0 hop of MIDI analyses: the pitch tracker's (256 samples at 22 050 Hz).
pub const MIDI_F0_HOP_S: f64 = 256.0 / 22_050.0;

/// f0 of the highest sounding note per frame (0 where nothing sounds), voiced 1 or 0.
fn f0_of(notes: &[Note], duration_s: f64) -> F0Track {
    let frames = (duration_s / MIDI_F0_HOP_S).ceil().max(0.0) as usize;
    let mut top = vec![0u8; frames];
    for n in notes {
        let first = (n.onset_s / MIDI_F0_HOP_S).ceil().max(0.0) as usize;
        let last = ((n.offset_s / MIDI_F0_HOP_S).ceil().max(0.0) as usize).min(frames);
        for t in top.iter_mut().take(last).skip(first) {
            *t = (*t).max(n.midi);
        }
    }
    F0Track {
        hop_s: MIDI_F0_HOP_S,
        hz: top
            .iter()
            .map(|&m| {
                if m == 0 {
                    0.0
                } else {
                    (440.0 * 2f64.powf((f64::from(m) - 69.0) / 12.0)) as f32
                }
            })
            .collect(),
        voiced_prob: top.iter().map(|&m| f32::from(u8::from(m > 0))).collect(),
    }
}

impl Pipeline {
    /// The [`Performance`] of a MIDI file: its melodic line with bowing by the rules of
    /// `performance::midi`, and the chords' other notes as its second voice
    /// ([`Performance::double_stops`]). Every note is fingered together, as in
    /// [`Pipeline::analyze_midi_file`], so the line's places leave its double stops in reach.
    pub fn performance_from_midi(&self, path: impl AsRef<Path>) -> Result<Performance> {
        self.refuse_beat_hints_for_midi()?;
        let score = score_from_midi_file(path, &self.midi_options())?;
        let mut timeline = timeline_from_score(&score);
        let all: Vec<Note> = score
            .notes
            .iter()
            .map(|n| Note::new(n.onset_s, n.offset_s, n.midi))
            .collect();
        let mut places = self.plan(&all);
        // The line keeps each chord's first note (the highest) in score order; the notes it
        // drops are the second voice.
        let mut in_line = vec![false; all.len()];
        let mut next = 0;
        for timed in &mut timeline.notes {
            let n = &timed.note;
            let found = all[next..]
                .iter()
                .position(|a| a.onset_s == n.onset_s && a.midi == n.midi);
            if let Some(k) = found {
                in_line[next + k] = true;
                timed.note.fingering = places[next + k].take();
                next += k + 1;
            }
        }
        let double_stops: Vec<Note> = all
            .iter()
            .zip(places)
            .zip(&in_line)
            .filter(|(_, &line)| !line)
            .map(|((n, fingering), _)| Note { fingering, ..*n })
            .collect();
        let line = timeline.to_performance()?;
        Ok(Performance::new(performance::PerformanceParts {
            double_stops,
            ..line.into()
        })?)
    }

    /// The analysis of a MIDI file (see `performance::midi` for the rules): every note as
    /// the file has it (onset, offset, pitch, velocity; overlapping notes kept as double
    /// stops) with string, position and finger; beats, downbeats and meter from the tempo
    /// map and time signatures (inferred from the notes without one); bow changes from the
    /// slur rules on the melodic line, stroke directions by [`performance::bow_directions`];
    /// arousal from velocity and note density; f0 of the highest sounding note.
    /// `sample_rate` is 0 (no audio).
    pub fn analyze_midi_file(&self, path: impl AsRef<Path>) -> Result<Analysis> {
        self.refuse_beat_hints_for_midi()?;
        let score = score_from_midi_file(path, &self.midi_options())?;
        Ok(self.analyze_midi_score(&score))
    }

    /// [`Pipeline::analyze_midi_file`] on a score already read.
    pub fn analyze_midi_score(&self, score: &MidiScore) -> Analysis {
        let timeline = timeline_from_score(score);
        let bare: Vec<Note> = score
            .notes
            .iter()
            .map(|n| Note {
                velocity: Some(n.velocity),
                ..Note::new(n.onset_s, n.offset_s, n.midi)
            })
            .collect();
        let notes: Vec<Note> = bare
            .iter()
            .zip(self.plan(&bare))
            .map(|(n, fingering)| Note { fingering, ..*n })
            .collect();
        let bow_changes_s = timeline.bow_changes_s();
        let directions = bow_directions(&bow_changes_s, &notes, &score.downbeats_s);
        let bow_strokes = performance::strokes_of(&bow_changes_s, &directions, &notes);
        let spans: Vec<(f64, f64, f32)> = score
            .notes
            .iter()
            .map(|n| (n.onset_s, n.offset_s, f32::from(n.velocity) / 127.0))
            .collect();
        Analysis {
            schema_version: ANALYSIS_SCHEMA_VERSION,
            source: "midi".into(),
            duration_s: score.duration_s,
            sample_rate: 0,
            f0: f0_of(&notes, score.duration_s),
            notes,
            bow_strokes,
            bow_changes_s,
            bow_directions: directions,
            beats_s: score.beats_s.clone(),
            downbeats_s: score.downbeats_s.clone(),
            tempo_bpm: score.tempo_bpm,
            tempo_bpm_per_beat: performance::tempo_per_beat(&score.beats_s),
            meter: Some(score.meter),
            beat_confidence: Some(1.0),
            arousal: ArousalCurve::deam(arousal_proxy_of_spans(&spans, score.duration_s)),
        }
    }
}
