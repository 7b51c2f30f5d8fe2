//! Where a passage is going: the learned planner's span context. Violinists plan for the
//! notes ahead (a high note a few notes on → move up the neck now; a passage that never goes
//! low → stay up), while the melodic context of [`crate::context`] sees only the
//! neighbouring intervals. The span class of a note joins the register of the highest
//! note among it and the next [`SpanContext::ahead`] notes with that of the lowest note
//! around it; [`crate::LearnedPlanner`] refines P(place | pitch, melodic context) by it.

use std::collections::BTreeMap;

use crate::fingering::Fingering;

/// Upper bounds (MIDI) of the high-note buckets: the highest note the D, A and E strings
/// reach in 1st position (A4, E5, B5), the E string in 3rd (E6) and in 5th (A6).
const HIGH_BOUNDS: [u8; 5] = [69, 76, 83, 88, 93];
/// Upper bounds (MIDI) of the low-note buckets: below the open D, A and E strings, below D5
/// (the A string's 3rd position) and below A5.
const LOW_BOUNDS: [u8; 5] = [61, 68, 73, 75, 80];
/// Buckets per side (one more than the bounds).
const BUCKETS: usize = HIGH_BOUNDS.len() + 1;
/// Span classes: high-note bucket × low-note bucket.
pub const SPAN_CLASSES: usize = BUCKETS * BUCKETS;

/// How the span context is read and weighed (stored with the learned parameters).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpanContext {
    /// Notes after the note whose highest pitch sets the high bucket.
    pub ahead: usize,
    /// Notes before the note that join the next `ahead` in the lowest pitch.
    pub behind: usize,
    /// Pseudo-counts of P(place | pitch, context, span) towards P(place | pitch, context).
    pub alpha: f64,
    /// Weight of the refinement (0: off; 1: the refined probability replaces the context's).
    pub weight: f64,
}

fn bucket(bounds: &[u8], midi: u8) -> usize {
    bounds.iter().take_while(|&&b| midi > b).count()
}

/// The span class of note `i` of `midi` (0..[`SPAN_CLASSES`]): the bucket of the highest
/// pitch among the note and the `ahead` notes after it, joined with the bucket of the
/// lowest pitch among the `behind` notes before, the note and the `ahead` after.
///
/// ```
/// use fingering::span::span_class;
/// let arpeggio = [69, 74, 76, 78, 79, 79, 83, 86, 91];
/// // From D5 the next four notes reach G5, and nothing lower than D5 comes:
/// // a different class from the same D5 with an A4 among the notes around it.
/// assert_ne!(span_class(&arpeggio, 1, 4, 0), span_class(&arpeggio, 1, 4, 1));
/// assert!(usize::from(span_class(&arpeggio, 8, 4, 8)) < fingering::span::SPAN_CLASSES);
/// ```
pub fn span_class(midi: &[u8], i: usize, ahead: usize, behind: usize) -> u8 {
    let end = i.saturating_add(ahead).saturating_add(1).min(midi.len());
    let high = midi.get(i..end).and_then(|w| w.iter().max().copied());
    let low = midi
        .get(i.saturating_sub(behind)..end)
        .and_then(|w| w.iter().min().copied());
    let high = bucket(&HIGH_BOUNDS, high.unwrap_or(0));
    let low = bucket(&LOW_BOUNDS, low.unwrap_or(0));
    (high * BUCKETS + low) as u8
}

/// Counts of where each pitch was played per (pitch, melodic context, span class): per place
/// of the planner's list for that pitch, and their total.
#[derive(Debug, Default)]
pub(crate) struct SpanTable {
    counts: BTreeMap<(u8, u8, u8), (Vec<f64>, f64)>,
}

impl SpanTable {
    /// The table of `counts` (keyed as [`crate::LearnedParams::span_emission`]) over the
    /// planner's places, `places[pitch - lowest]`; places outside them are ignored.
    pub(crate) fn new(
        counts: &BTreeMap<(u8, u8, u8, Fingering), u32>,
        lowest: u8,
        places: &[Vec<Fingering>],
    ) -> SpanTable {
        let mut table = SpanTable::default();
        for (&(midi, ctx, class, f), &n) in counts {
            let Some(list) = midi
                .checked_sub(lowest)
                .and_then(|k| places.get(usize::from(k)))
            else {
                continue;
            };
            let Some(k) = list.iter().position(|g| *g == f) else {
                continue;
            };
            let entry = table
                .counts
                .entry((midi, ctx, class))
                .or_insert_with(|| (vec![0.0; list.len()], 0.0));
            entry.0[k] += f64::from(n);
            entry.1 += f64::from(n);
        }
        table
    }

    /// The counts of one (pitch, melodic context, span class): per place, and their total
    /// (`None` where it was never counted).
    pub(crate) fn counts(&self, key: (u8, u8, u8)) -> Option<&(Vec<f64>, f64)> {
        self.counts.get(&key)
    }
}

/// The change to place `k`'s emission cost `e` (= −ln P(place | pitch, context)) given the
/// counts of its (pitch, context, span class) ([`SpanTable::counts`]): `weight · (−ln
/// P(place | pitch, context, span) − e)`, the refined probability smoothed towards the
/// context's with `alpha` pseudo-counts; 0 where the (pitch, context, span) was never
/// counted.
pub(crate) fn span_cost(
    counts: Option<&(Vec<f64>, f64)>,
    k: usize,
    e: f64,
    span: &SpanContext,
) -> f64 {
    let Some((c, n)) = counts else {
        return 0.0;
    };
    let refined = (c.get(k).copied().unwrap_or(0.0) + span.alpha * (-e).exp()) / (n + span.alpha);
    span.weight * (-refined.ln() - e)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ViolinString;

    #[test]
    fn classes_follow_the_highest_note_ahead_and_the_lowest_around() {
        let arpeggio = [69, 74, 76, 78, 79, 79, 83, 86, 91];
        // From D5: four notes on reach G5 (bucket 2), the lowest is D5 (above C#5: 3).
        assert_eq!(span_class(&arpeggio, 1, 4, 0), (2 * BUCKETS + 3) as u8);
        // One note behind brings in the open A (above G#4, not above C#5: 2).
        assert_eq!(span_class(&arpeggio, 1, 4, 1), (2 * BUCKETS + 2) as u8);
        // Eight notes on reach G6 (above E6: 4).
        assert_eq!(span_class(&arpeggio, 1, 8, 0), (4 * BUCKETS + 3) as u8);
        assert_eq!(span_class(&[], 0, 4, 0), 0);
        assert_eq!(span_class(&arpeggio, 100, 4, 2), 0);
        assert_eq!(span_class(&[55], 0, usize::MAX, usize::MAX), 0);
    }

    #[test]
    fn the_refinement_moves_costs_towards_the_span_counts() {
        let a = Fingering::new(ViolinString::A, 1, 1);
        let b = Fingering::new(ViolinString::A, 3, 1);
        let mut counts = BTreeMap::new();
        counts.insert((71, 3, 7, b), 9);
        counts.insert((71, 3, 7, a), 1);
        let table = SpanTable::new(&counts, 55, &vec![vec![a, b]; 20]);
        let span = SpanContext {
            ahead: 4,
            behind: 0,
            alpha: 2.0,
            weight: 1.0,
        };
        let e = -(0.5f64.ln());
        // The span's counts favour b: its cost falls, a's rises.
        assert!(span_cost(table.counts((71, 3, 7)), 1, e, &span) < 0.0);
        assert!(span_cost(table.counts((71, 3, 7)), 0, e, &span) > 0.0);
        // Never counted: no change.
        assert_eq!(span_cost(table.counts((71, 3, 8)), 0, e, &span), 0.0);
        let off = SpanContext {
            weight: 0.0,
            ..span
        };
        assert_eq!(span_cost(table.counts((71, 3, 7)), 1, e, &off), 0.0);
    }
}
