//! Fingering of analysed notes: the planner the pipeline was built with, the style knobs,
//! *sul* passages in seconds, and double stops.

use fingering::{
    partner_place, Fingering, FingeringPlanner, FingeringStyle, FingeringTable, GreedyPlanner,
    LearnedPlanner, OptimalPlanner, ViolinString,
};
use performance::Note;

/// Which fingering planner places the notes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PlannerKind {
    /// The original design's greedy rule (on the physical fingerboard model, so every pitch
    /// G3..A7 gets a place).
    Greedy,
    /// Viterbi over the physical model's places with hand-set costs.
    Optimal,
    /// Viterbi over costs learned from ten violinists (TNUA dataset; default: it agrees
    /// with the violinists more often than the others on the held-out pieces).
    #[default]
    Learned,
}

/// A passage played on one string (*sul G*, *sul D*, …), in seconds: notes starting in
/// `[from_s, to_s)` stay on `string` wherever it can play them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SulSpan {
    /// The string.
    pub string: ViolinString,
    /// Start of the passage in seconds.
    pub from_s: f64,
    /// End of the passage in seconds.
    pub to_s: f64,
}

/// One place per note (`None` for a note no violin place plays): the notes of the melodic
/// line (each note that does not sound together with the line's current note) go through
/// the planner with the style, each line note of a double stop in a place from which its
/// nearest partner can be stopped on the neighbouring string wherever one allows it
/// ([`fingering::FingeringStyle::double_stop`]); the other notes of a double stop or chord
/// take the neighbouring strings ([`fingering::partner_place`]).
pub(crate) fn plan_notes(
    kind: PlannerKind,
    style: &FingeringStyle,
    sul: &[SulSpan],
    notes: &[Note],
) -> Vec<Option<Fingering>> {
    let table = FingeringTable::physical();
    let playable = |n: &Note| !table.places(n.midi).is_empty();
    let partner_of = performance::double_stop_partners(notes, playable);
    let line: Vec<usize> = (0..notes.len())
        .filter(|&i| partner_of[i].is_none() && playable(&notes[i]))
        .collect();
    let pitches: Vec<u8> = line.iter().map(|&i| notes[i].midi).collect();
    let mut style = style.clone();
    // Each line note with partners keeps the nearest in pitch within reach (the one on the
    // neighbouring string).
    let mut nearest: Vec<Option<u8>> = vec![None; notes.len()];
    for (n, partner) in notes.iter().zip(&partner_of) {
        let Some(l) = *partner else { continue };
        let line_midi = notes[l].midi;
        if nearest[l].is_none_or(|m| n.midi.abs_diff(line_midi) < m.abs_diff(line_midi)) {
            nearest[l] = Some(n.midi);
        }
    }
    for (k, &l) in line.iter().enumerate() {
        if let Some(m) = nearest[l] {
            style = style.double_stop(k, m);
        }
    }
    for span in sul {
        let from = line.partition_point(|&i| notes[i].onset_s < span.from_s);
        let to = line.partition_point(|&i| notes[i].onset_s < span.to_s);
        style = style.sul(span.string, from..to);
    }
    let plan = match kind {
        PlannerKind::Greedy => GreedyPlanner::new(table).plan(&pitches),
        PlannerKind::Optimal => OptimalPlanner::default().with_style(style).plan(&pitches),
        PlannerKind::Learned => LearnedPlanner::default().with_style(style).plan(&pitches),
    }
    .unwrap_or_default();
    let mut out = vec![None; notes.len()];
    for (&i, f) in line.iter().zip(plan) {
        out[i] = Some(f);
    }
    for (i, partner) in partner_of.iter().enumerate() {
        if let Some(line_place) = partner.and_then(|l| out[l]) {
            out[i] = partner_place(&line_place, notes[i].midi);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn double_stops_sit_on_neighbouring_strings() {
        // A4 with D4 below for a second, then B4 alone.
        let notes = [
            Note::new(0.0, 1.0, 69),
            Note::new(0.0, 1.0, 62),
            Note::new(1.0, 2.0, 71),
        ];
        let plan = plan_notes(
            PlannerKind::Learned,
            &FingeringStyle::default(),
            &[],
            &notes,
        );
        let (a, d) = (plan[0].unwrap(), plan[1].unwrap());
        assert_eq!(a.midi(), 69);
        assert_eq!(d.midi(), 62);
        assert_eq!(
            i32::from(a.string.number()) - i32::from(d.string.number()),
            1
        );
        assert!(plan[2].is_some());
        // A legato overlap of 20 ms is not a double stop.
        let legato = [Note::new(0.0, 1.02, 69), Note::new(1.0, 2.0, 71)];
        let plan = plan_notes(
            PlannerKind::Optimal,
            &FingeringStyle::default(),
            &[],
            &legato,
        );
        assert!(plan.iter().all(|f| f.is_some()));
    }

    #[test]
    fn a_double_stop_moves_its_line_note_to_where_the_partner_is_in_reach() {
        // D5, then E5 over G4 (a sixth), then F#5 over A4: alone, E5 would be the open E,
        // which leaves G4 no string next to it.
        let notes = [
            Note::new(0.0, 0.5, 74),
            Note::new(0.5, 1.0, 76),
            Note::new(0.5, 1.0, 67),
            Note::new(1.0, 1.5, 78),
            Note::new(1.0, 1.5, 69),
        ];
        for kind in [PlannerKind::Learned, PlannerKind::Optimal] {
            let plan = plan_notes(kind, &FingeringStyle::default(), &[], &notes);
            for (top, low) in [(1, 2), (3, 4)] {
                let (top, low) = (plan[top].unwrap(), plan[low].unwrap());
                assert_eq!(top.string.number(), low.string.number() + 1, "{kind:?}");
                assert!(low.is_open() || low.position.abs_diff(top.position) <= 1);
            }
        }
    }

    #[test]
    fn sul_spans_in_seconds_keep_the_passage_on_its_string() {
        let notes: Vec<Note> = [62u8, 64, 66, 67, 69, 71]
            .iter()
            .enumerate()
            .map(|(i, &m)| Note::new(i as f64 * 0.5, i as f64 * 0.5 + 0.5, m))
            .collect();
        let sul = [SulSpan {
            string: ViolinString::G,
            from_s: 0.0,
            to_s: 10.0,
        }];
        let plan = plan_notes(
            PlannerKind::Learned,
            &FingeringStyle::default(),
            &sul,
            &notes,
        );
        assert!(plan
            .iter()
            .all(|f| f.is_some_and(|f| f.string == ViolinString::G)));
        // Below G3 nothing plays: no place, no panic.
        let low = plan_notes(
            PlannerKind::Greedy,
            &FingeringStyle::default(),
            &[],
            &[Note::new(0.0, 1.0, 40)],
        );
        assert_eq!(low, vec![None]);
    }
}
