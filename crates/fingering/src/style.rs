//! Style knobs shared by the optimal and learned planners: open strings, low or high
//! positions, a fixed string for a passage (*sul G*), and the double stops the music asks
//! for.

use std::ops::Range;

use serde::{Deserialize, Serialize};

use crate::fingering::Fingering;
use crate::partner::double_stop_place;
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

/// A note of the planned line that sounds with another note (a double stop): its place
/// must let the hand stop `partner_midi` on the neighbouring string
/// ([`crate::double_stop_place`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct DoubleStopNote {
    /// The note, by index in the planner's input.
    pub note: usize,
    /// The pitch that sounds with it.
    pub partner_midi: u8,
}

/// How a player likes to finger, on top of a planner's own costs. Each knob adds a cost
/// (in the planner's units: the learned planner's are nats, about "how many times less
/// likely", the optimal planner's are its [`crate::CostWeights`] units) to a place:
///
/// * `open_string`: added to every open-string note; > 0 avoids open strings, < 0 seeks
///   them (an open G3 stays: nothing else plays it);
/// * `position`: added per position number above the first for every note; > 0 keeps the
///   hand low, < 0 sends it up the neck (a cheap way to get a darker, one-string sound);
/// * `sul`: passages kept on one string ([`SulPassage`]);
/// * `double_stops`: notes that sound with another ([`DoubleStopNote`]): a place from which
///   the other note is out of reach is refused whenever the note has a place from which it
///   is in reach (within the *sul* string, if any).
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
    /// Double stops, sorted by note ([`FingeringStyle::double_stop`] keeps them so).
    pub double_stops: Vec<DoubleStopNote>,
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

    /// The same style with note `note` sounding with `partner_midi` (a double stop).
    ///
    /// ```
    /// use fingering::{FingeringPlanner, FingeringStyle, LearnedPlanner, ViolinString};
    /// // D5 then E5 with G4 under it: E5 leaves the open E for the A string.
    /// let style = FingeringStyle::default().double_stop(1, 67);
    /// let plan = LearnedPlanner::default().with_style(style).plan(&[74, 76])?;
    /// assert_eq!(plan[1].string, ViolinString::A);
    /// # Ok::<(), fingering::FingeringError>(())
    /// ```
    pub fn double_stop(mut self, note: usize, partner_midi: u8) -> FingeringStyle {
        let at = self.double_stops.partition_point(|d| d.note <= note);
        self.double_stops
            .insert(at, DoubleStopNote { note, partner_midi });
        self
    }

    /// `true` when the style changes nothing.
    pub fn is_neutral(&self) -> bool {
        self.open_string == 0.0
            && self.position == 0.0
            && self.sul.is_empty()
            && self.double_stops.is_empty()
    }

    /// The pitch that sounds with note `index`, if it is a double stop (the last one listed
    /// for it).
    pub fn partner_midi(&self, index: usize) -> Option<u8> {
        let end = self.double_stops.partition_point(|d| d.note <= index);
        end.checked_sub(1)
            .and_then(|k| self.double_stops.get(k))
            .filter(|d| d.note == index)
            .map(|d| d.partner_midi)
    }

    /// Whether the *sul* passage over note `index`, if any, allows `place`.
    fn sul_allows(&self, index: usize, place: &Fingering, places: &[Fingering]) -> bool {
        self.sul_string(index).is_none_or(|string| {
            place.string == string || !places.iter().any(|p| p.string == string)
        })
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
    /// (infinite for a place off the passage's string when the string can play the note,
    /// and for a place that leaves a double stop's other note out of reach when another
    /// place would not).
    pub fn place_cost(&self, index: usize, place: &Fingering, places: &[Fingering]) -> f64 {
        if !self.sul_allows(index, place, places) {
            return f64::INFINITY;
        }
        if let Some(partner) = self.partner_midi(index) {
            let reach = |p: &Fingering| double_stop_place(p, partner).is_some();
            if !reach(place)
                && places
                    .iter()
                    .any(|p| reach(p) && self.sul_allows(index, p, places))
            {
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
            ..FingeringStyle::default()
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

    #[test]
    fn double_stops_refuse_places_that_leave_the_partner_out_of_reach() {
        let style = FingeringStyle::default()
            .double_stop(3, 60)
            .double_stop(1, 67);
        assert_eq!(style.partner_midi(1), Some(67));
        assert_eq!(style.partner_midi(3), Some(60));
        assert_eq!(style.partner_midi(2), None);
        assert!(!style.is_neutral());
        let open_e = Fingering::open(ViolinString::E, 1);
        let e5_on_a = Fingering::new(ViolinString::A, 3, 2);
        let places = [e5_on_a, open_e];
        assert!(style.place_cost(1, &open_e, &places).is_infinite());
        assert_eq!(style.place_cost(1, &e5_on_a, &places), 0.0);
        // Not a double stop: both allowed.
        assert_eq!(style.place_cost(0, &open_e, &places), 0.0);
        // When no place reaches the partner, none is refused.
        let only_e = [open_e];
        assert_eq!(style.place_cost(1, &open_e, &only_e), 0.0);
        // Sul E keeps the E string even though the partner is then out of reach.
        let sul_e = style.sul(ViolinString::E, 0..4);
        assert_eq!(sul_e.place_cost(1, &open_e, &places), 0.0);
        assert!(sul_e.place_cost(1, &e5_on_a, &places).is_infinite());
    }
}
