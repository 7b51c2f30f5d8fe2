//! The original design's greedy planner.

use crate::error::FingeringError;
use crate::fingering::Fingering;
use crate::planner::FingeringPlanner;
use crate::table::FingeringTable;

/// The original design's greedy rule (SPEC §6, the seed's Algorithm 2), exactly:
///
/// 1. the first note goes to the **lowest position** that plays it;
/// 2. a note equal to the previous one **keeps its place** (the skeleton changes only when
///    the note changes);
/// 3. otherwise, if the current position plays the note, **stay** in it;
/// 4. else move to the **nearest position** that plays the note, nearest by position
///    number; a tie (one position below and one above) goes to the **lower** position.
///
/// Within the chosen position the place listed **first** in the table is taken (the
/// original and physical tables list lower strings first, so e.g. D4 in first position
/// is the G string's 4th finger before the open D). Positions compare by number, the half
/// position (0) being the lowest; the original table has no half position, while with the
/// physical table — which lists an open string in every position — an opening open string
/// starts in the half position, as the rule says.
///
/// ```
/// use fingering::{FingeringPlanner, GreedyPlanner, ViolinString};
/// let plan = GreedyPlanner::default().plan(&[67, 69, 71])?; // G4 A4 B4
/// assert!(plan.iter().all(|f| f.position == 1));
/// assert_eq!(plan[0].string, ViolinString::D);
/// # Ok::<(), fingering::FingeringError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GreedyPlanner {
    table: FingeringTable,
}

impl GreedyPlanner {
    /// A greedy planner over `table`.
    pub fn new(table: FingeringTable) -> GreedyPlanner {
        GreedyPlanner { table }
    }

    /// The table the planner chooses from.
    pub fn table(&self) -> &FingeringTable {
        &self.table
    }
}

impl Default for GreedyPlanner {
    /// The seed's planner: the original table.
    fn default() -> Self {
        GreedyPlanner::new(FingeringTable::original())
    }
}

impl FingeringPlanner for GreedyPlanner {
    fn plan(&self, midi: &[u8]) -> Result<Vec<Fingering>, FingeringError> {
        let mut plan: Vec<Fingering> = Vec::with_capacity(midi.len());
        let mut previous: Option<(u8, Fingering)> = None;
        for (index, &note) in midi.iter().enumerate() {
            let places = self.table.places(note);
            if places.is_empty() {
                return Err(FingeringError::UnplayablePitch { index, midi: note });
            }
            let place = match previous {
                Some((last, place)) if last == note => place,
                Some((_, place)) => choose(places, Some(place.position)),
                None => choose(places, None),
            };
            plan.push(place);
            previous = Some((note, place));
        }
        Ok(plan)
    }
}

/// The first place listed in the position nearest `current` (ties: the lower position);
/// with no current position, in the lowest position. `places` is not empty.
fn choose(places: &[Fingering], current: Option<u8>) -> Fingering {
    let distance = |position: u8| match current {
        Some(current) => position.abs_diff(current),
        None => position,
    };
    let mut best = places[0];
    for &place in &places[1..] {
        let (d, best_d) = (distance(place.position), distance(best.position));
        if d < best_d || (d == best_d && place.position < best.position) {
            best = place;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ViolinString;

    #[test]
    fn choose_prefers_the_current_then_the_nearest_then_the_lower_position() {
        let g = ViolinString::G;
        let places = [
            Fingering::new(g, 4, 1),
            Fingering::new(g, 2, 3),
            Fingering::new(g, 2, 4),
        ];
        assert_eq!(choose(&places, None), places[1]);
        assert_eq!(choose(&places, Some(4)), places[0]);
        assert_eq!(choose(&places, Some(3)), places[1]); // tie 2 vs 4 -> lower
        assert_eq!(choose(&places, Some(5)), places[0]);
        assert_eq!(choose(&places, Some(1)), places[1]);
    }
}
