//! The original table as embedded, and the physical model's table.

use fingering::physical::{self, HIGHEST_MIDI, LOWEST_MIDI};
use fingering::{Fingering, FingeringTable, Placement, ViolinString, ORIGINAL_TABLE_TSV};

fn spf(f: &Fingering) -> String {
    format!("{}-{}-{}", f.string.number(), f.position, f.finger)
}

#[test]
fn the_embedded_original_table_parses_to_34_notes_g3_to_e6() {
    let strict = FingeringTable::from_tsv(ORIGINAL_TABLE_TSV).expect("embedded table parses");
    assert_eq!(strict, FingeringTable::original());
    assert_eq!(strict.len(), 34);
    assert_eq!(
        strict.pitches().collect::<Vec<_>>(),
        (55..=88).collect::<Vec<u8>>()
    );
    // Entries and their order are kept as published.
    let c4: Vec<String> = strict.places(60).iter().map(spf).collect();
    assert_eq!(c4, ["1-1-3", "1-2-2", "1-3-1"]);
    let d4: Vec<String> = strict.places(62).iter().map(spf).collect();
    assert_eq!(d4, ["1-1-4", "1-2-3", "1-3-2", "1-4-1", "2-1-0"]);
    let e6: Vec<String> = strict.places(88).iter().map(spf).collect();
    assert_eq!(e6, ["4-4-4", "4-5-3", "4-6-2", "4-7-1"]);
    assert!(strict.places(54).is_empty());
    assert!(strict.places(89).is_empty());
}

#[test]
fn original_places_play_their_note_within_a_semitone_under_the_physical_model() {
    let table = FingeringTable::original();
    for midi in table.pitches() {
        for place in table.places(midi) {
            assert!(place.is_physical(), "{midi}: {place:?}");
            let off = (i32::from(place.midi()) - i32::from(midi)).abs();
            assert!(off <= 1, "{midi}: {} plays {}", spf(place), place.midi());
        }
    }
}

/// What the README documents: the entries that the physical model plays a semitone away
/// from the note they are listed for (the original's semitone pairs share entries).
#[test]
fn the_inexact_original_entries_are_the_documented_ones() {
    let table = FingeringTable::original();
    let mut inexact = Vec::new();
    for midi in table.pitches() {
        for place in table.places(midi) {
            if place.midi() != midi {
                inexact.push(format!("{midi}:{}->{}", spf(place), place.midi()));
            }
        }
    }
    let expected = [
        "58:1-1-1->57",
        "61:1-3-1->60",
        "63:1-3-2->62",
        "63:1-4-1->62",
        "68:2-3-1->67",
        "70:2-3-2->69",
        "70:2-4-1->69",
        "70:3-1-0->69",
        "75:3-3-1->74",
        "77:3-2-4->78",
        "82:4-3-1->81",
        "84:4-2-4->85",
        "87:4-6-1->86",
    ];
    assert_eq!(inexact, expected);
    let total: usize = table.pitches().map(|m| table.places(m).len()).sum();
    assert_eq!(total, 125);
    // Sharps that share the natural's entries get the high/low finger when it exists.
    assert_eq!(
        table.places(61)[0],
        Fingering::with_placement(ViolinString::G, 1, 3, Placement::High)
    );
}

#[test]
fn every_pitch_g3_to_a7_has_a_physical_place_playing_exactly_it() {
    let table = FingeringTable::physical();
    assert_eq!(table.len(), usize::from(HIGHEST_MIDI - LOWEST_MIDI) + 1);
    for midi in LOWEST_MIDI..=HIGHEST_MIDI {
        let places = table.places(midi);
        assert!(!places.is_empty(), "no place for {midi}");
        for place in places {
            assert_eq!(place.midi(), midi, "{place:?}");
            assert!(place.is_physical(), "{place:?}");
        }
    }
    assert!(table.places(LOWEST_MIDI - 1).is_empty());
    assert!(table.places(HIGHEST_MIDI + 1).is_empty());
    assert_eq!(table.max_places(), 26); // as the README says
}

#[test]
fn the_physical_table_lists_every_place_of_the_model() {
    let table = FingeringTable::physical();
    let mut count = 0;
    for string in ViolinString::ALL {
        for position in 0..=physical::max_position(string) {
            for finger in 0..=4 {
                for placement in [Placement::Low, Placement::Normal, Placement::High] {
                    let place = Fingering::with_placement(string, position, finger, placement);
                    if !place.is_physical() || place.midi() > HIGHEST_MIDI {
                        continue;
                    }
                    count += 1;
                    assert!(table.places(place.midi()).contains(&place), "{place:?}");
                }
            }
        }
    }
    let listed: usize = table.pitches().map(|m| table.places(m).len()).sum();
    assert_eq!(listed, count);
}

#[test]
fn open_strings_are_listed_in_every_position_of_their_string() {
    let table = FingeringTable::physical();
    for string in ViolinString::ALL {
        let places = table.places(string.open_midi());
        let open: Vec<u8> = places
            .iter()
            .filter(|f| f.string == string)
            .map(|f| {
                assert!(f.is_open());
                f.position
            })
            .collect();
        assert_eq!(
            open,
            (0..=physical::max_position(string)).collect::<Vec<_>>()
        );
    }
    // E5 can also be stopped on the A string (4th finger in first position, ...).
    assert!(table
        .places(76)
        .contains(&Fingering::new(ViolinString::A, 1, 4)));
}

#[test]
fn only_the_extended_e_string_reaches_the_top() {
    let table = FingeringTable::physical();
    for midi in 100..=HIGHEST_MIDI {
        assert!(table
            .places(midi)
            .iter()
            .all(|f| f.string == ViolinString::E && f.position > physical::MAX_POSITION));
    }
    assert_eq!(table.places(105), &[Fingering::new(ViolinString::E, 14, 4)]);
}
