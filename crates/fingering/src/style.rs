//! Style knobs shared by the optimal and learned planners: open strings, low or high
//! positions, and a fixed string for a passage (*sul G*).

use std::ops::Range;

use serde::{Deserialize, Serialize};

use crate::fingering::Fingering;
use crate::string::ViolinString;

/// A passage (notes `notes`, indices into the planner's input) played on one string
/// wherever that string can play the note (a note it cannot play keeps its other places).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SulPassage {
    /// The string the passage stays on.
    pub string: ViolinString,
    /// The notes of the passage, by index in the planner's input.
    pub notes: Range<usize>,
}

/// How a player likes to finger, on top of a planner's own costs. Each knob adds a cost
/// (in the planner's units: the learned planner's are nats, about "how many times less
/// likely", the optimal planner's are its [`crate::CostWeights`] units) to a place:
///
/// * `open_string`: added to every open-string note; > 0 avoids open strings, < 0 seeks
///   them (an open G3 stays: nothing else plays it);
/// * `position`: added per position number above the first for every note; > 0 keeps the
///   hand low, < 0 sends it up the neck (a cheap way to get a darker, one-string sound);
/// * `sul`: passages kept on one string ([`SulPassage`]).
///
/// The default changes nothing. Presets: [`FingeringStyle::avoid_open_strings`],
/// [`FingeringStyle::prefer_open_strings`], [`FingeringStyle::low_positions`],
/// [`FingeringStyle::high_positions`].
///
/// ```
/// use fingering::{FingeringPlanner, FingeringStyle, LearnedPlanner, ViolinString};
/// // D5 E5 F#5 G5 sul G: the whole passage on the G string, high up.
/// let style = FingeringStyle::default().sul(ViolinString::G, 0..4);
/// let plan = LearnedPlanner::default().with_style(style).plan(&[74, 76, 78, 79])?;
/// assert!(plan.iter().all(|f| f.string == ViolinString::G));
/// # Ok::<(), fingering::FingeringError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct FingeringStyle {
    /// Cost per open-string note (< 0 prefers open strings).
    pub open_string: f32,
    /// Cost per position number above the first, per note (< 0 prefers high positions).
    pub position: f32,
    /// Passages kept on one string.
    pub sul: Vec<SulPassage>,
}

impl FingeringStyle {
    /// Open strings only where nothing else plays the note (a cost far above any shift).
    pub fn avoid_open_strings() -> FingeringStyle {
        FingeringStyle {
            open_string: 20.0,
            ..FingeringStyle::default()
        }
    }

    /// Open strings wherever they are within reach.
    pub fn prefer_open_strings() -> FingeringStyle {
        FingeringStyle {
            open_string: -1.0,
            ..FingeringStyle::default()
        }
    }

    /// Stay as low on the neck as the notes allow.
    pub fn low_positions() -> FingeringStyle {
        FingeringStyle {
            position: 0.5,
            ..FingeringStyle::default()
        }
    }

    /// Play higher on the neck (fewer string crossings, a darker sound).
    pub fn high_positions() -> FingeringStyle {
        FingeringStyle {
            position: -1.0,
            ..FingeringStyle::default()
        }
    }

    /// The same style with one more *sul* passage.
    pub fn sul(mut self, string: ViolinString, notes: Range<usize>) -> FingeringStyle {
        self.sul.push(SulPassage { string, notes });
        self
    }

    /// `true` when the style changes nothing.
    pub fn is_neutral(&self) -> bool {
        self.open_string == 0.0 && self.position == 0.0 && self.sul.is_empty()
    }

    /// The string note `index` must stay on, if a passage covers it (the last passage
    /// listed wins).
    pub fn sul_string(&self, index: usize) -> Option<ViolinString> {
        self.sul
            .iter()
            .rev()
            .find(|p| p.notes.contains(&index))
            .map(|p| p.string)
    }

    /// The style's cost of `place` for note `index`, given the note's other `places`
    /// (infinite for a place off the passage's string when the string can play the note).
    pub fn place_cost(&self, index: usize, place: &Fingering, places: &[Fingering]) -> f64 {
        if let Some(string) = self.sul_string(index) {
            if place.string != string && places.iter().any(|p| p.string == string) {
                return f64::INFINITY;
            }
        }
        let mut cost = 0.0;
        if place.is_open() && places.iter().any(|p| !p.is_open()) {
            cost += f64::from(self.open_string);
        }
        cost + f64::from(self.position) * (f64::from(place.position) - 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sul_forbids_other_strings_only_where_the_string_plays_the_note() {
        let style = FingeringStyle::default().sul(ViolinString::D, 1..3);
        let g_places = [Fingering::new(ViolinString::G, 1, 1)];
        let d = Fingering::new(ViolinString::D, 1, 1);
        let a = Fingering::new(ViolinString::A, 1, 1);
        assert!(style.place_cost(1, &a, &[a, d]).is_infinite());
        assert_eq!(style.place_cost(1, &d, &[a, d]), 0.0);
        assert_eq!(style.place_cost(0, &a, &[a, d]), 0.0); // outside the passage
        assert_eq!(style.place_cost(2, &g_places[0], &g_places), 0.0); // D cannot play it
    }

    #[test]
    fn open_and_position_costs() {
        let style = FingeringStyle {
            open_string: 1.5,
            position: 0.5,
            sul: Vec::new(),
        };
        let open = Fingering::open(ViolinString::A, 3);
        let stopped = Fingering::new(ViolinString::D, 3, 4);
        assert_eq!(style.place_cost(0, &open, &[open, stopped]), 1.5 + 1.0);
        assert_eq!(style.place_cost(0, &stopped, &[open, stopped]), 1.0);
        // G3 has only open places: no open-string cost.
        let g = Fingering::open(ViolinString::G, 1);
        assert_eq!(style.place_cost(0, &g, &[g]), 0.0);
        assert!(FingeringStyle::default().is_neutral());
    }
}
