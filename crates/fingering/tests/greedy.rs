//! The seed's greedy rule on crafted sequences.

use fingering::{
    Fingering, FingeringError, FingeringPlanner, FingeringTable, GreedyPlanner, ViolinString,
};

use ViolinString::{A, D, E, G};

fn spf(plan: &[Fingering]) -> Vec<(ViolinString, u8, u8)> {
    plan.iter()
        .map(|f| (f.string, f.position, f.finger))
        .collect()
}

#[test]
fn the_first_note_goes_to_the_lowest_position_that_plays_it() {
    let greedy = GreedyPlanner::default();
    // D5: 2-4-4 3-1-3 3-2-2 3-3-1 -> first position although listed second.
    assert_eq!(spf(&greedy.plan(&[74]).unwrap()), [(A, 1, 3)]);
    // C6: 4-2-4 4-3-3 4-4-2 4-5-1 -> second position.
    assert_eq!(spf(&greedy.plan(&[84]).unwrap()), [(E, 2, 4)]);
    // D4 in first position: the G string's 4th finger is listed before the open D.
    assert_eq!(spf(&greedy.plan(&[62]).unwrap()), [(G, 1, 4)]);
}

#[test]
fn it_stays_in_position_while_the_note_is_playable_there() {
    let greedy = GreedyPlanner::default();
    // C6 starts in 2nd position; D5 (2-4-4 3-1-3 3-2-2 3-3-1) stays in 2nd although 1st
    // also plays it, and so does E4 (1-2-4 ...).
    let plan = greedy.plan(&[84, 74, 64]).unwrap();
    assert_eq!(spf(&plan), [(E, 2, 4), (A, 2, 2), (G, 2, 4)]);
    // G4 A4 B4 C5 D5 in first position.
    let plan = greedy.plan(&[67, 69, 71, 72, 74]).unwrap();
    assert!(plan.iter().all(|f| f.position == 1), "{plan:?}");
    assert_eq!(spf(&plan)[1], (D, 1, 4)); // A4: 2-1-4 listed before the open A
}

#[test]
fn a_forced_move_goes_to_the_nearest_position() {
    let greedy = GreedyPlanner::default();
    // From 2nd position, E6 (4-4-4 4-5-3 4-6-2 4-7-1) goes to 4th, the nearest; then A4
    // (2-1-4 2-2-3 2-3-2 2-4-1 3-1-0) stays in 4th.
    let plan = greedy.plan(&[84, 88, 69]).unwrap();
    assert_eq!(spf(&plan), [(E, 2, 4), (E, 4, 4), (D, 4, 1)]);
    // From 4th (E6 first), G3 forces the open G in 1st: its only place.
    let plan = greedy.plan(&[88, 55]).unwrap();
    assert_eq!(spf(&plan), [(E, 4, 4), (G, 1, 0)]);
}

#[test]
fn a_tie_between_two_nearest_positions_goes_to_the_lower_one() {
    let table = FingeringTable::from_tsv(
        "note\tmidi\tplaces\nC4\t60\t1-3-1\nD4\t62\t1-4-1 1-2-3\nE4\t64\t2-3-1 2-1-1\n",
    )
    .unwrap();
    let greedy = GreedyPlanner::new(table);
    // C4 -> 3rd; D4 is in 2nd and 4th (listed first), both one away -> 2nd.
    let plan = greedy.plan(&[60, 62]).unwrap();
    assert_eq!(spf(&plan), [(G, 3, 1), (G, 2, 3)]);
    // From 2nd, E4 is in 1st and 3rd -> 1st.
    let plan = greedy.plan(&[60, 62, 64]).unwrap();
    assert_eq!(spf(&plan)[2], (D, 1, 1));
    // From 3rd, E4 stays in 3rd.
    let plan = greedy.plan(&[60, 64]).unwrap();
    assert_eq!(spf(&plan)[1], (D, 3, 1));
}

#[test]
fn within_a_position_the_first_listed_place_is_taken() {
    let table =
        FingeringTable::from_tsv("E5\t76\t4-1-0 3-1-4\nA4\t69\t3-1-0\nD5\t74\t3-1-3\n").unwrap();
    let greedy = GreedyPlanner::new(table);
    assert_eq!(spf(&greedy.plan(&[76]).unwrap()), [(E, 1, 0)]);
    let original = GreedyPlanner::default();
    assert_eq!(spf(&original.plan(&[76]).unwrap()), [(A, 1, 4)]);
}

#[test]
fn a_repeated_note_keeps_its_place() {
    for greedy in [
        GreedyPlanner::default(),
        GreedyPlanner::new(FingeringTable::physical()),
    ] {
        let notes = [84, 84, 74, 74, 74, 88, 88, 69, 69];
        let plan = greedy.plan(&notes).unwrap();
        for i in 1..notes.len() {
            if notes[i] == notes[i - 1] {
                assert_eq!(plan[i], plan[i - 1]);
            }
        }
    }
}

#[test]
fn with_the_physical_table_an_opening_open_string_starts_in_half_position() {
    let greedy = GreedyPlanner::new(FingeringTable::physical());
    let plan = greedy.plan(&[55, 57]).unwrap();
    assert_eq!(plan[0], Fingering::open(G, 0));
    assert_eq!(plan[1].position, 0);
    assert!(plan.iter().zip([55, 57]).all(|(f, m)| f.midi() == m));
    // A7 only exists on the extended E string.
    assert_eq!(greedy.plan(&[105]).unwrap(), [Fingering::new(E, 14, 4)]);
}

#[test]
fn unplayable_pitches_are_typed_errors_and_empty_input_is_empty() {
    let greedy = GreedyPlanner::default();
    assert_eq!(greedy.plan(&[]).unwrap(), []);
    assert_eq!(
        greedy.plan(&[60, 40]),
        Err(FingeringError::UnplayablePitch { index: 1, midi: 40 })
    );
    assert_eq!(
        greedy.plan(&[120]),
        Err(FingeringError::UnplayablePitch {
            index: 0,
            midi: 120
        })
    );
    // The original table stops at E6 (MIDI 88); the physical one goes on to A7.
    assert_eq!(
        greedy.plan(&[88, 89]),
        Err(FingeringError::UnplayablePitch { index: 1, midi: 89 })
    );
    let physical = GreedyPlanner::new(FingeringTable::physical());
    assert!(physical.plan(&[88, 89, 105]).is_ok());
    assert!(physical.plan(&[106]).is_err());
    let message = greedy.plan(&[40]).unwrap_err().to_string();
    assert!(message.contains("MIDI 40"), "{message}");
}
