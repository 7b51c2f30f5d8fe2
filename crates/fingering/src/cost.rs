//! The cost of a fingering plan, minimised by [`crate::OptimalPlanner`].

use serde::{Deserialize, Serialize};

use crate::fingering::Fingering;
use crate::physical;
use crate::placement::Placement;

/// Tunable weights of the fingering cost. A plan's cost is the sum over its notes of a
/// **place cost** ([`CostWeights::place_cost`]) plus, between consecutive notes, a
/// **transition cost** ([`CostWeights::transition_cost`]):
///
/// * shift: `shift + shift_per_semitone · |Δhand|` when the position changes, where `hand`
///   is [`Fingering::hand_offset_semitones`] (semitones along the neck);
/// * string crossing: `string_crossing · |Δstring number|` (per string crossed);
/// * high position: `high_position · max(0, hand - 2)` per note (semitones above first
///   position), and `half_position` per note in the half position;
/// * `open_string` per open-string note (0 by default: open strings are as good as any
///   finger) — or forbid them with `forbid_open_strings`;
/// * `fourth_finger` per note stopped by the little finger (the weakest; it makes an open
///   string win over a 4th finger when both are otherwise equal, as in first-position
///   scales);
/// * `altered_finger` per low or high finger ([`Placement`]): it favours the position whose
///   normal finger pattern fits the passage (C major from D5 sits in third position with
///   every finger normal, while second position would need five low or high fingers), and
///   `extension` on top for an extended 4th finger (the hand's widest stretch).
///
/// All weights should be ≥ 0. Missing fields take their defaults when read with serde.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CostWeights {
    /// Fixed cost of any change of position. Default 1.0.
    pub shift: f32,
    /// Cost per semitone the hand travels in a shift. Default 0.25.
    pub shift_per_semitone: f32,
    /// Cost per string crossed between consecutive notes. Default 0.25.
    pub string_crossing: f32,
    /// Cost per note per semitone of the hand above first position. Default 0.06.
    pub high_position: f32,
    /// Cost per note played in the half position. Default 0.3.
    pub half_position: f32,
    /// Cost per open-string note. Default 0.0.
    pub open_string: f32,
    /// Never use an open string for a note that has a stopped place (G3, which has none,
    /// stays on the open G). Default false.
    pub forbid_open_strings: bool,
    /// Cost per note stopped by the 4th finger. Default 0.1.
    pub fourth_finger: f32,
    /// Cost per low or high finger ([`Placement::Low`], [`Placement::High`]). Default 0.15.
    pub altered_finger: f32,
    /// Cost per extended 4th finger ([`Placement::High`] on finger 4), on top of
    /// `fourth_finger` and `altered_finger`. Default 0.3.
    pub extension: f32,
}

impl Default for CostWeights {
    fn default() -> Self {
        CostWeights {
            shift: 1.0,
            shift_per_semitone: 0.25,
            string_crossing: 0.25,
            high_position: 0.06,
            half_position: 0.3,
            open_string: 0.0,
            forbid_open_strings: false,
            fourth_finger: 0.1,
            altered_finger: 0.15,
            extension: 0.3,
        }
    }
}

impl CostWeights {
    /// The cost of playing a note at `place`, regardless of its neighbours.
    pub fn place_cost(&self, place: &Fingering) -> f64 {
        let hand = f64::from(place.hand_offset_semitones());
        let first = f64::from(physical::position_offset(1));
        let mut cost = f64::from(self.high_position) * (hand - first).max(0.0);
        if place.position == physical::HALF_POSITION {
            cost += f64::from(self.half_position);
        }
        if place.placement != Placement::Normal {
            cost += f64::from(self.altered_finger);
        }
        match place.finger {
            0 => cost += f64::from(self.open_string),
            4 => {
                cost += f64::from(self.fourth_finger);
                if place.placement == Placement::High {
                    cost += f64::from(self.extension);
                }
            }
            _ => {}
        }
        cost
    }

    /// The cost of moving from `from` to `to` between consecutive notes: shift and string
    /// crossing.
    pub fn transition_cost(&self, from: &Fingering, to: &Fingering) -> f64 {
        let strings = i32::from(from.string.number()) - i32::from(to.string.number());
        let mut cost = f64::from(self.string_crossing) * f64::from(strings.abs());
        if from.position != to.position {
            let travel = from.hand_offset_semitones() - to.hand_offset_semitones();
            cost += f64::from(self.shift)
                + f64::from(self.shift_per_semitone) * f64::from(travel.abs());
        }
        cost
    }

    /// The total cost of a plan: every place cost plus every transition cost.
    /// (`forbid_open_strings` is a constraint of the planner, not a cost.)
    pub fn path_cost(&self, plan: &[Fingering]) -> f64 {
        let places: f64 = plan.iter().map(|f| self.place_cost(f)).sum();
        let moves: f64 = plan
            .windows(2)
            .map(|w| self.transition_cost(&w[0], &w[1]))
            .sum();
        places + moves
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ViolinString;

    #[test]
    fn costs_follow_the_documented_formulas() {
        let w = CostWeights::default();
        let first = Fingering::new(ViolinString::A, 1, 1);
        let third = Fingering::new(ViolinString::E, 3, 1);
        assert_eq!(w.place_cost(&first), 0.0);
        assert!((w.place_cost(&third) - 0.06 * 3.0).abs() < 1e-6);
        // Shift 1st -> 3rd (2 -> 5 semitones) and one string crossed.
        let expected = 0.25 + 1.0 + 0.25 * 3.0;
        assert!((w.transition_cost(&first, &third) - expected).abs() < 1e-6);
        assert_eq!(w.transition_cost(&first, &first), 0.0);
        let half = Fingering::new(ViolinString::A, 0, 1);
        assert!((w.place_cost(&half) - 0.3).abs() < 1e-6);
        let x4 = Fingering::with_placement(ViolinString::A, 1, 4, Placement::High);
        assert!((w.place_cost(&x4) - 0.55).abs() < 1e-6);
        let low2 = Fingering::with_placement(ViolinString::A, 1, 2, Placement::Low);
        assert!((w.place_cost(&low2) - 0.15).abs() < 1e-6);
        let path = [first, third, first];
        let total = w.path_cost(&path);
        assert!((total - (2.0 * expected + 0.18)).abs() < 1e-6);
    }

    #[test]
    fn serde_round_trip_and_defaults_for_missing_fields() {
        let w = CostWeights::default();
        let text = serde_json::to_string(&w).unwrap();
        assert_eq!(serde_json::from_str::<CostWeights>(&text).unwrap(), w);
        let partial: CostWeights = serde_json::from_str(r#"{"shift": 5.0}"#).unwrap();
        assert_eq!(partial.shift, 5.0);
        assert_eq!(partial.string_crossing, w.string_crossing);
    }
}
