//! Property tests: optimality against the greedy plan and random plans, determinism, and
//! the greedy rule's invariants.

use fingering::{
    CostWeights, Fingering, FingeringPlanner, FingeringTable, GreedyPlanner, OptimalPlanner,
};
use proptest::prelude::*;

fn melody(low: u8, high: u8) -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(low..=high, 0..80)
}

/// Melodies that move like music: small steps, some leaps, repeated notes.
fn stepwise(low: u8, high: u8) -> impl Strategy<Value = Vec<u8>> {
    (low..=high, prop::collection::vec(-7i8..=7, 0..80)).prop_map(move |(start, steps)| {
        let mut note = start;
        let mut out = vec![note];
        for step in steps {
            note = note.saturating_add_signed(step).clamp(low, high);
            out.push(note);
        }
        out
    })
}

fn weights() -> impl Strategy<Value = CostWeights> {
    (
        (0.0f32..3.0, 0.0f32..1.0, 0.0f32..1.0, 0.0f32..0.3),
        (
            0.0f32..1.0,
            0.0f32..1.0,
            0.0f32..1.0,
            0.0f32..1.0,
            0.0f32..1.0,
        ),
    )
        .prop_map(
            |((shift, per, crossing, high), (half, open, finger, altered, extension))| {
                CostWeights {
                    shift,
                    shift_per_semitone: per,
                    string_crossing: crossing,
                    high_position: high,
                    half_position: half,
                    open_string: open,
                    forbid_open_strings: false,
                    fourth_finger: finger,
                    altered_finger: altered,
                    extension,
                }
            },
        )
}

proptest! {
    #[test]
    fn optimal_costs_no_more_than_greedy(notes in melody(55, 105), w in weights()) {
        let optimal = OptimalPlanner::with_weights(w);
        let greedy = GreedyPlanner::new(FingeringTable::physical());
        let (plan, cost) = optimal.plan_with_cost(&notes).unwrap();
        let greedy_plan = greedy.plan(&notes).unwrap();
        prop_assert_eq!(plan.len(), notes.len());
        prop_assert!(cost <= w.path_cost(&greedy_plan) + 1e-9);
    }

    #[test]
    fn optimal_costs_no_more_than_random_plans(
        notes in stepwise(55, 105),
        picks in prop::collection::vec(any::<prop::sample::Index>(), 81),
    ) {
        let optimal = OptimalPlanner::default();
        let table = optimal.table();
        let (_, cost) = optimal.plan_with_cost(&notes).unwrap();
        let random: Vec<Fingering> = notes
            .iter()
            .zip(&picks)
            .map(|(&m, pick)| *pick.get(table.places(m)))
            .collect();
        prop_assert!(cost <= optimal.weights.path_cost(&random) + 1e-9);
    }

    #[test]
    fn optimal_plans_are_deterministic_and_play_the_notes(notes in stepwise(55, 105)) {
        let first = OptimalPlanner::default().plan_with_cost(&notes).unwrap();
        let second = OptimalPlanner::default().plan_with_cost(&notes).unwrap();
        prop_assert_eq!(&first, &second);
        let table = FingeringTable::physical();
        for (place, &m) in first.0.iter().zip(&notes) {
            prop_assert_eq!(place.midi(), m);
            prop_assert!(table.places(m).contains(place));
        }
    }

    #[test]
    fn greedy_follows_the_seed_rule(
        notes in stepwise(55, 88),
        physical in any::<bool>(),
    ) {
        let table = if physical { FingeringTable::physical() } else { FingeringTable::original() };
        let plan = GreedyPlanner::new(table.clone()).plan(&notes).unwrap();
        prop_assert_eq!(plan.len(), notes.len());
        for (i, (&m, place)) in notes.iter().zip(&plan).enumerate() {
            let places = table.places(m);
            prop_assert!(places.contains(place));
            let first_in = |p: u8| places.iter().find(|f| f.position == p).copied();
            if i == 0 {
                let lowest = places.iter().map(|f| f.position).min().unwrap();
                prop_assert_eq!(Some(*place), first_in(lowest));
            } else if notes[i - 1] == m {
                prop_assert_eq!(*place, plan[i - 1]);
            } else {
                let current = plan[i - 1].position;
                let best = places
                    .iter()
                    .map(|f| (f.position.abs_diff(current), f.position))
                    .min()
                    .unwrap();
                prop_assert_eq!(Some(*place), first_in(best.1));
            }
        }
    }
}
