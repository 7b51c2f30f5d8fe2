//! The optimal (Viterbi) planner: the plan of least total cost.

use crate::cost::CostWeights;
use crate::error::FingeringError;
use crate::fingering::Fingering;
use crate::planner::FingeringPlanner;
use crate::string::ViolinString;
use crate::style::FingeringStyle;
use crate::table::FingeringTable;

/// Chooses, among all places of every note, the plan of least total cost under
/// [`CostWeights`] (shifts, string crossings, high positions, open strings, weak or
/// stretched fingers) by dynamic programming (Viterbi) over the places of consecutive
/// notes: O(n · k²) time for n notes of at most k places each (k ≤ 30 in the physical
/// table), O(n · k) memory for the back-pointers, and no allocation per note.
///
/// Ties between equally cheap plans go to the place listed first in the table, so planning
/// is deterministic. With `forbid_open_strings`, open places are left out for every note
/// that has a stopped place. Unlike the greedy rule, a repeated note may change place
/// (e.g. a shift on a repeated note) when that makes the whole plan cheaper.
///
/// ```
/// use fingering::{FingeringPlanner, OptimalPlanner, ViolinString};
/// // A major, A4..A5: first position, crossing to the open E halfway.
/// let plan = OptimalPlanner::default().plan(&[69, 71, 73, 74, 76, 78, 80, 81])?;
/// assert!(plan.iter().all(|f| f.position == 1));
/// assert_eq!((plan[4].string, plan[4].finger), (ViolinString::E, 0));
/// # Ok::<(), fingering::FingeringError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct OptimalPlanner {
    /// The cost weights the plan minimises.
    pub weights: CostWeights,
    table: FingeringTable,
    style: FingeringStyle,
}

impl Default for OptimalPlanner {
    /// The physical table with default weights.
    fn default() -> Self {
        OptimalPlanner::new(FingeringTable::physical(), CostWeights::default())
    }
}

/// What the inner loop needs of a place, precomputed once per note.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    position: u8,
    string: f64,
    hand: f64,
    /// Place cost, or infinity for a place the planner may not use.
    cost: f64,
}

impl OptimalPlanner {
    /// A planner over `table` minimising the cost under `weights`.
    pub fn new(table: FingeringTable, weights: CostWeights) -> OptimalPlanner {
        OptimalPlanner {
            weights,
            table,
            style: FingeringStyle::default(),
        }
    }

    /// The same planner with style knobs ([`FingeringStyle`], in [`CostWeights`] units).
    pub fn with_style(mut self, style: FingeringStyle) -> OptimalPlanner {
        self.style = style;
        self
    }

    /// The physical table with the given weights.
    pub fn with_weights(weights: CostWeights) -> OptimalPlanner {
        OptimalPlanner::new(FingeringTable::physical(), weights)
    }

    /// The table the planner chooses from.
    pub fn table(&self) -> &FingeringTable {
        &self.table
    }

    /// Like [`FingeringPlanner::plan`], also returning the plan's total cost
    /// ([`CostWeights::path_cost`], without the style's costs).
    pub fn plan_with_cost(&self, midi: &[u8]) -> Result<(Vec<Fingering>, f64), FingeringError> {
        let mut total_places = 0usize;
        for (index, &note) in midi.iter().enumerate() {
            match self.table.places(note).len() {
                0 => return Err(FingeringError::UnplayablePitch { index, midi: note }),
                k => total_places += k,
            }
        }
        if midi.is_empty() {
            return Ok((Vec::new(), 0.0));
        }
        let k_max = self.table.max_places();
        // back[offset(i) + j]: the best predecessor (index into note i-1's places) of place j
        // of note i; offsets are recovered while walking back.
        let mut back: Vec<u32> = Vec::with_capacity(total_places);
        let mut previous: Vec<Candidate> = Vec::with_capacity(k_max);
        let mut current: Vec<Candidate> = Vec::with_capacity(k_max);
        let mut score: Vec<f64> = Vec::with_capacity(k_max);
        let mut next_score: Vec<f64> = Vec::with_capacity(k_max);

        for (index, &note) in midi.iter().enumerate() {
            self.candidates(index, self.table.places(note), &mut current);
            next_score.clear();
            if previous.is_empty() {
                next_score.extend(current.iter().map(|c| c.cost));
                back.extend(std::iter::repeat_n(0, current.len()));
            } else {
                for to in &current {
                    let (mut best, mut best_from) = (f64::INFINITY, 0u32);
                    for (i, (from, &s)) in previous.iter().zip(&score).enumerate() {
                        let total = s + self.transition(from, to);
                        if total < best {
                            best = total;
                            best_from = i as u32;
                        }
                    }
                    next_score.push(best + to.cost);
                    back.push(best_from);
                }
            }
            std::mem::swap(&mut previous, &mut current);
            std::mem::swap(&mut score, &mut next_score);
        }

        let (mut j, mut best) = (0usize, f64::INFINITY);
        for (i, &s) in score.iter().enumerate() {
            if s < best {
                (j, best) = (i, s);
            }
        }
        let mut plan = vec![Fingering::open(ViolinString::G, 0); midi.len()];
        let mut end = back.len();
        for (slot, &note) in plan.iter_mut().zip(midi).rev() {
            let places = self.table.places(note);
            if let Some(&place) = places.get(j) {
                *slot = place;
            }
            let start = end - places.len();
            j = back.get(start + j).map_or(0, |&b| b as usize);
            end = start;
        }
        let total = self.weights.path_cost(&plan);
        Ok((plan, total))
    }

    /// Fills `out` with the candidates of note `index`'s `places`.
    fn candidates(&self, index: usize, places: &[Fingering], out: &mut Vec<Candidate>) {
        let forbid_open = self.weights.forbid_open_strings && places.iter().any(|f| !f.is_open());
        out.clear();
        out.extend(places.iter().map(|f| Candidate {
            position: f.position,
            string: f64::from(f.string.number()),
            hand: f64::from(f.hand_offset_semitones()),
            cost: if forbid_open && f.is_open() {
                f64::INFINITY
            } else if self.style.is_neutral() {
                self.weights.place_cost(f)
            } else {
                self.weights.place_cost(f) + self.style.place_cost(index, f, places)
            },
        }));
    }

    /// [`CostWeights::transition_cost`] on precomputed candidates.
    #[inline]
    fn transition(&self, from: &Candidate, to: &Candidate) -> f64 {
        let w = &self.weights;
        let mut cost = f64::from(w.string_crossing) * (from.string - to.string).abs();
        if from.position != to.position {
            cost +=
                f64::from(w.shift) + f64::from(w.shift_per_semitone) * (from.hand - to.hand).abs();
        }
        cost
    }
}

impl FingeringPlanner for OptimalPlanner {
    fn plan(&self, midi: &[u8]) -> Result<Vec<Fingering>, FingeringError> {
        self.plan_with_cost(midi).map(|(plan, _)| plan)
    }
}
