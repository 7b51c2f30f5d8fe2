//! The optimal planner fingers scales, arpeggios and position passages the standard way.

use std::time::{Duration, Instant};

use fingering::{
    CostWeights, Fingering, FingeringError, FingeringPlanner, FingeringTable, OptimalPlanner,
    ViolinString,
};

use ViolinString::{A, D, E, G};

fn spf(plan: &[Fingering]) -> Vec<(ViolinString, u8, u8)> {
    plan.iter()
        .map(|f| (f.string, f.position, f.finger))
        .collect()
}

fn optimal(notes: &[u8]) -> Vec<Fingering> {
    let plan = match OptimalPlanner::default().plan(notes) {
        Ok(plan) => plan,
        Err(error) => panic!("{notes:?}: {error}"),
    };
    assert_eq!(plan.len(), notes.len());
    for (f, &m) in plan.iter().zip(notes) {
        assert_eq!(f.midi(), m, "{f:?}");
    }
    plan
}

fn shifts(plan: &[Fingering]) -> usize {
    plan.windows(2)
        .filter(|w| w[0].position != w[1].position)
        .count()
}

const G_MAJOR: [u8; 15] = [55, 57, 59, 60, 62, 64, 66, 67, 69, 71, 72, 74, 76, 78, 79];
const G_MAJOR_FINGERING: [(ViolinString, u8, u8); 15] = [
    (G, 1, 0),
    (G, 1, 1),
    (G, 1, 2),
    (G, 1, 3),
    (D, 1, 0),
    (D, 1, 1),
    (D, 1, 2),
    (D, 1, 3),
    (A, 1, 0),
    (A, 1, 1),
    (A, 1, 2),
    (A, 1, 3),
    (E, 1, 0),
    (E, 1, 1),
    (E, 1, 2),
];

#[test]
fn g_major_two_octaves_in_first_position_with_open_strings() {
    assert_eq!(spf(&optimal(&G_MAJOR)), G_MAJOR_FINGERING);
    let mut down = G_MAJOR;
    down.reverse();
    let mut expected = G_MAJOR_FINGERING;
    expected.reverse();
    assert_eq!(spf(&optimal(&down)), expected);
}

#[test]
fn g_major_arpeggio_and_a_major_scale_in_first_position() {
    let arpeggio = optimal(&[55, 59, 62, 67, 71, 74, 79, 74, 71, 67, 62, 59, 55]);
    assert_eq!(
        spf(&arpeggio[..7]),
        [
            (G, 1, 0),
            (G, 1, 2),
            (D, 1, 0),
            (D, 1, 3),
            (A, 1, 1),
            (A, 1, 3),
            (E, 1, 2)
        ]
    );
    assert_eq!(shifts(&arpeggio), 0);
    let a_major = optimal(&[69, 71, 73, 74, 76, 78, 80, 81]);
    assert_eq!(
        spf(&a_major),
        [
            (A, 1, 0),
            (A, 1, 1),
            (A, 1, 2),
            (A, 1, 3),
            (E, 1, 0),
            (E, 1, 1),
            (E, 1, 2),
            (E, 1, 3)
        ]
    );
}

#[test]
fn a_passage_sitting_in_third_position_shifts_there_once_and_stays() {
    // G3 A3 B3 C4 on the G string (A3 only exists in half and first position), then C major
    // figures D5..D6 on the A and E strings: third position with every finger normal.
    let mut notes = vec![55, 57, 59, 60];
    let figure = [86, 84, 83, 81, 79, 77, 79, 81, 83, 84];
    for _ in 0..4 {
        notes.extend(figure);
    }
    notes.push(86);
    let plan = optimal(&notes);
    assert_eq!(shifts(&plan), 1, "{:?}", spf(&plan));
    assert_eq!(plan[1].position, 1);
    let third: Vec<_> = plan.iter().skip_while(|f| f.position != 3).collect();
    assert!(third.len() >= notes.len() - 4, "{:?}", spf(&plan));
    assert!(third.iter().all(|f| f.position == 3));
    // In third position: G5 and F5 on the A string, A5..D6 on the E string.
    let f = &plan[4..14];
    assert_eq!(
        spf(f),
        [
            (E, 3, 4),
            (E, 3, 3),
            (E, 3, 2),
            (E, 3, 1),
            (A, 3, 4),
            (A, 3, 3),
            (A, 3, 4),
            (E, 3, 1),
            (E, 3, 2),
            (E, 3, 3)
        ]
    );
    assert!(f.iter().all(|f| f.placement.is_normal()));
}

#[test]
fn a_high_passage_goes_to_a_high_position_on_the_e_string() {
    // E6 F#6 G6 A6 ... : seventh position on the E string, every finger normal.
    let notes = [88, 90, 91, 93, 91, 90, 88, 90, 91, 93];
    let plan = optimal(&notes);
    assert!(
        plan.iter().all(|f| f.string == E && f.position == 7),
        "{:?}",
        spf(&plan)
    );
    // Up to E7 and back: everything above the A string's reach is on the E string in a
    // position of 7 or more, with few shifts.
    let notes = [88, 89, 91, 93, 95, 96, 98, 100, 98, 96, 95, 93, 91, 89, 88];
    let plan = optimal(&notes);
    for (f, &m) in plan.iter().zip(&notes) {
        assert!(f.position >= 7, "{:?}", spf(&plan));
        if m > 92 {
            assert_eq!(f.string, E);
        }
    }
    assert!(shifts(&plan) <= 2, "{:?}", spf(&plan));
    // A7 needs the E string's extension.
    let top = OptimalPlanner::default()
        .plan(&[100, 101, 103, 105])
        .unwrap();
    assert!(top.iter().all(|f| f.string == E && f.position == 14));
}

#[test]
fn no_needless_shifts_back_and_forth() {
    // A long first-position tune with wide leaps: never leaves first position.
    let tune = [
        55, 62, 71, 79, 74, 67, 59, 64, 72, 76, 81, 78, 69, 60, 57, 66, 74, 79, 71, 62,
    ];
    let plan = optimal(&tune);
    assert_eq!(shifts(&plan), 0, "{:?}", spf(&plan));
    // A trill and a repeated note keep their places.
    let trill = optimal(&[83, 84, 83, 84, 83, 84, 84, 84]);
    assert_eq!(shifts(&trill), 0);
    assert_eq!(trill[5], trill[6]);
    // A single high note in a first-position passage: up once and down once at most.
    let excursion = optimal(&[67, 71, 74, 79, 83, 86, 83, 79, 74, 71, 67, 71, 74]);
    assert!(shifts(&excursion) <= 2, "{:?}", spf(&excursion));
}

#[test]
fn open_strings_can_be_penalised_or_forbidden() {
    let forbid = OptimalPlanner::with_weights(CostWeights {
        forbid_open_strings: true,
        ..CostWeights::default()
    });
    let plan = forbid.plan(&G_MAJOR).unwrap();
    // G3 has no stopped place and stays open; D4, A4, E5 become 4th fingers.
    assert_eq!(plan[0], Fingering::open(G, 1));
    assert!(plan[1..].iter().all(|f| !f.is_open()), "{plan:?}");
    assert_eq!(spf(&plan)[4], (G, 1, 4));
    assert_eq!(spf(&plan)[8], (D, 1, 4));
    let penalise = OptimalPlanner::with_weights(CostWeights {
        open_string: 1.0,
        ..CostWeights::default()
    });
    assert_eq!(penalise.plan(&G_MAJOR).unwrap(), plan);
}

#[test]
fn reported_cost_is_the_path_cost_and_a_worse_plan_costs_more() {
    let planner = OptimalPlanner::default();
    let (plan, cost) = planner.plan_with_cost(&G_MAJOR).unwrap();
    assert_eq!(cost, planner.weights.path_cost(&plan));
    let mut worse = plan.clone();
    worse[4] = Fingering::new(G, 1, 4);
    worse[8] = Fingering::new(D, 3, 2);
    assert!(planner.weights.path_cost(&worse) > cost);
}

#[test]
fn works_with_the_original_table_too() {
    let planner = OptimalPlanner::new(FingeringTable::original(), CostWeights::default());
    let plan = planner.plan(&G_MAJOR).unwrap();
    assert_eq!(spf(&plan), G_MAJOR_FINGERING);
    assert!(planner.plan(&[89]).is_err());
}

#[test]
fn unplayable_pitches_are_typed_errors_and_empty_input_is_empty() {
    let planner = OptimalPlanner::default();
    assert_eq!(planner.plan(&[]).unwrap(), []);
    assert_eq!(planner.plan_with_cost(&[]).unwrap(), (vec![], 0.0));
    assert_eq!(
        planner.plan(&[67, 69, 40]),
        Err(FingeringError::UnplayablePitch { index: 2, midi: 40 })
    );
    assert_eq!(
        planner.plan(&[120, 67]),
        Err(FingeringError::UnplayablePitch {
            index: 0,
            midi: 120
        })
    );
    assert_eq!(
        planner.plan(&[54]),
        Err(FingeringError::UnplayablePitch { index: 0, midi: 54 })
    );
}

#[test]
fn ten_thousand_notes_plan_well_under_100_ms() {
    let mut state: u32 = 0x2545_f491;
    let notes: Vec<u8> = (0..10_000)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            55 + (state % 51) as u8
        })
        .collect();
    let planner = OptimalPlanner::default();
    // Open-string pitches have the most places (up to the table's maximum).
    let opens: Vec<u8> = (0..10_000).map(|i| [55, 62, 69, 76][i % 4]).collect();
    for input in [&notes, &opens] {
        let best = (0..3)
            .map(|_| {
                let start = Instant::now();
                let plan = planner.plan(input).unwrap();
                assert_eq!(plan.len(), input.len());
                start.elapsed()
            })
            .min()
            .unwrap();
        assert!(best < Duration::from_millis(100), "took {best:?}");
    }
}
