//! [`Timeline`]: a played piece with its articulation and labels, before it becomes a
//! [`Performance`].

use crate::arousal::{arousal_proxy_of_spans, ArousalCurve};
use crate::error::PerformanceError;
use crate::note::Note;
use crate::performance::Performance;

/// A note as played, with how it is played: a [`Note`] (times in seconds, the end of the
/// sound before the release tail, and its fingering once [`Timeline::assign_fingering`] ran)
/// and its articulation.
#[derive(Debug, Clone, PartialEq)]
pub struct TimedNote {
    /// When and what.
    pub note: Note,
    /// The note starts a new bow stroke (a bow change, or the first stroke after a rest).
    pub bow_change: bool,
    /// Dynamic level 0..=1.
    pub dynamic: f32,
    /// Accented attack.
    pub accent: bool,
}

/// A played piece with every label: notes with their articulation, beats, downbeats, an
/// arousal curve and the nominal tempo. The synthetic corpus plays its études into one and
/// MIDI files are read into one (`midi` feature); [`Timeline::to_performance`] turns it into
/// the [`Performance`] that motion synthesis animates.
#[derive(Debug, Clone, PartialEq)]
pub struct Timeline {
    /// Total length in seconds (the last bar line plus a short tail).
    pub duration_s: f64,
    /// Notes in time order.
    pub notes: Vec<TimedNote>,
    /// Every beat, in seconds.
    pub beats_s: Vec<f64>,
    /// Every downbeat (first beat of each bar), in seconds.
    pub downbeats_s: Vec<f64>,
    /// Arousal proxy at 2 Hz in [-1, 1] (see [`arousal_proxy`]).
    pub arousal_2hz: Vec<f32>,
    /// Nominal tempo in bpm.
    pub tempo_bpm: f64,
}

impl Timeline {
    /// Plans every note's fingering with `planner` (a note it cannot play keeps `None`).
    pub fn assign_fingering(&mut self, planner: &dyn fingering::FingeringPlanner) {
        let midi: Vec<u8> = self.notes.iter().map(|n| n.note.midi).collect();
        if let Ok(plan) = planner.plan(&midi) {
            for (n, f) in self.notes.iter_mut().zip(plan) {
                n.note.fingering = Some(f);
            }
        }
    }

    /// Onsets of the notes that start a bow stroke.
    pub fn bow_changes_s(&self) -> Vec<f64> {
        self.notes
            .iter()
            .filter(|n| n.bow_change)
            .map(|n| n.note.onset_s)
            .collect()
    }

    /// Joins strokes where a player hooks them so that bars start down-bow
    /// ([`crate::hooks_for_downbeats`], asking `may_hook` at each place): the later note is
    /// slurred onto the earlier one, which sounds until it starts. Returns the number of
    /// hooks.
    pub fn hook_to_downbeats(&mut self, may_hook: impl FnMut(usize) -> bool) -> usize {
        let notes: Vec<Note> = self.notes.iter().map(|n| n.note).collect();
        // The note that starts each stroke, in the order of `bow_changes_s`.
        let starts: Vec<usize> = (0..self.notes.len())
            .filter(|&i| self.notes[i].bow_change)
            .collect();
        let changes = self.bow_changes_s();
        let hooks = crate::hooks_for_downbeats(&changes, &notes, &self.downbeats_s, may_hook);
        for &h in &hooks {
            let Some(&j) = starts.get(h) else { continue };
            let t = self.notes[j].note.onset_s;
            self.notes[j].bow_change = false;
            if let Some(prev) = j.checked_sub(1).and_then(|p| self.notes.get_mut(p)) {
                prev.note.offset_s = prev.note.offset_s.max(t);
            }
        }
        hooks.len()
    }

    /// The timeline as a validated [`Performance`]: its notes (with their fingerings), bow
    /// changes, beats, downbeats, arousal and per-note dynamics.
    pub fn to_performance(&self) -> Result<Performance, PerformanceError> {
        let notes: Vec<Note> = self.notes.iter().map(|n| n.note).collect();
        let dynamics: Vec<f32> = self.notes.iter().map(|n| n.dynamic).collect();
        Performance::builder(self.duration_s)
            .notes(notes)
            .bow_changes(self.bow_changes_s())
            .beats(self.beats_s.clone())
            .downbeats(self.downbeats_s.clone())
            .arousal(ArousalCurve::deam(self.arousal_2hz.clone()))
            .dynamics(dynamics)
            .build()
    }
}

/// The arousal proxy at 2 Hz, in [-1, 1]: a documented stand-in for a listener's arousal
/// built from the correlates music-emotion research reports for it — loudness and event
/// density (Gabrielsson & Lindström 2010; Eerola & Vuoskoski 2013) — as far as they can be
/// heard in each half second:
///
/// `a(k) = tanh(1.8·(d̄(k) − 0.45) + 0.5·(ρ(k) − 3)/3)`
///
/// where `d̄` is the mean over the half second `[0.5k, 0.5k + 0.5)` of the dynamic of the
/// sounding note (0 where nothing sounds) and `ρ` the note onsets per second in the 2 s
/// around its centre; then smoothed with a [1, 2, 1]/4 kernel so it moves like DEAM's
/// annotations. (Version 1 sampled the dynamic at the frame's centre — a 30 ms gap between
/// détaché notes then read as silence — and added `0.9·(tempo − 110)/60` from the score's
/// bpm, which half-second frames cannot show: the speed they can hear is the event rate
/// `ρ`. See emotion-net's README.)
pub fn arousal_proxy(notes: &[TimedNote], duration_s: f64) -> Vec<f32> {
    let spans: Vec<(f64, f64, f32)> = notes
        .iter()
        .map(|n| (n.note.onset_s, n.note.offset_s, n.dynamic))
        .collect();
    arousal_proxy_of_spans(&spans, duration_s)
}
