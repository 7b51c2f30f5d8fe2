//! [`Pipeline::performance`]: the [`Performance`] an analysis describes.

use performance::{Analysis, ArousalCurve, Note, Performance};

use crate::error::{Error, Result};
use crate::pipeline::{Pipeline, MIN_DURATION_S};

/// An analysis's strokes inside `[0, duration_s]` with strictly increasing starts (a
/// hand-edited file may break either).
fn clip_strokes(
    strokes: &[performance::BowStroke],
    duration_s: f64,
) -> Vec<performance::BowStroke> {
    let mut out: Vec<performance::BowStroke> = Vec::with_capacity(strokes.len());
    for s in strokes {
        if !(s.start_s.is_finite() && s.end_s.is_finite()) {
            continue;
        }
        let start_s = s.start_s.clamp(0.0, duration_s);
        let end_s = s.end_s.clamp(start_s, duration_s);
        if out.last().is_none_or(|p| start_s > p.start_s) {
            out.push(performance::BowStroke {
                start_s,
                end_s,
                ..*s
            });
        }
    }
    out
}

impl Pipeline {
    /// The [`Performance`] an analysis describes (the fingering it carries is kept; notes
    /// without a place are re-planned; the other notes of double stops and chords become
    /// its second voice, [`Performance::double_stops`]).
    pub fn performance(&self, analysis: &Analysis) -> Result<Performance> {
        if analysis.duration_s < MIN_DURATION_S {
            return Err(Error::TooShort {
                source_name: "the recording".into(),
                duration_s: analysis.duration_s,
                min_s: MIN_DURATION_S,
            });
        }
        if analysis.notes.is_empty() {
            return Err(Error::NoNotes("the recording".into()));
        }
        let planned = self.plan(&analysis.notes);
        // Frame-centred analysis can put the last offset a hop past the end of the audio;
        // the performance covers exactly [0, duration].
        let duration_s = analysis.duration_s;
        let notes: Vec<Note> = analysis
            .notes
            .iter()
            .zip(planned)
            .filter(|(n, _)| n.onset_s < duration_s)
            .map(|(n, planned)| {
                let onset_s = n.onset_s.max(0.0);
                let offset_s = n.offset_s.min(duration_s).max(onset_s);
                Note {
                    onset_s,
                    offset_s,
                    fingering: n.fingering.or(planned),
                    ..*n
                }
            })
            .collect();
        // The other notes of double stops and chords (a MIDI analysis keeps them) are the
        // performance's second voice; the line stays monophonic.
        let partner_of = performance::double_stop_partners(&notes, |_| true);
        let (double_stops, notes): (Vec<_>, Vec<_>) = notes
            .into_iter()
            .zip(partner_of)
            .partition(|(_, partner)| partner.is_some());
        let inside = |t: &f64| *t >= 0.0 && *t <= analysis.duration_s;
        Ok(Performance::builder(analysis.duration_s)
            .notes(notes.into_iter().map(|(n, _)| n).collect())
            .double_stops(double_stops.into_iter().map(|(n, _)| n).collect())
            .bow_changes(
                analysis
                    .bow_changes_s
                    .iter()
                    .copied()
                    .filter(inside)
                    .collect(),
            )
            .beats(analysis.beats_s.iter().copied().filter(inside).collect())
            .downbeats(
                analysis
                    .downbeats_s
                    .iter()
                    .copied()
                    .filter(inside)
                    .collect(),
            )
            .arousal(ArousalCurve::clamped(
                analysis.arousal.rate_hz,
                analysis.arousal.values.clone(),
            ))
            .bow_strokes(clip_strokes(&analysis.bow_strokes, duration_s))
            .build()?)
    }
}
