//! Every place of the physical fingerboard model ([`crate::physical`]) that plays a pitch.

use crate::fingering::Fingering;
use crate::physical::{finger_offset, max_position, placements, position_offset, HALF_POSITION};
use crate::string::ViolinString;

/// Every place of the physical model that plays `midi`, ordered by string (G first), then
/// position (half position first); an open string is listed once per position of its
/// string. Empty outside the model's range.
pub fn places_for(midi: u8) -> Vec<Fingering> {
    let mut out = Vec::new();
    push_places_for(midi, &mut out);
    out
}

/// Appends the places of [`places_for`] to `out`.
pub(crate) fn push_places_for(midi: u8, out: &mut Vec<Fingering>) {
    for string in ViolinString::ALL {
        let Some(above) = midi.checked_sub(string.open_midi()) else {
            continue;
        };
        for position in HALF_POSITION..=max_position(string) {
            if above == 0 {
                out.push(Fingering::open(string, position));
                continue;
            }
            if let Some(place) = stop_in_position(string, position, above) {
                out.push(place);
            }
        }
    }
}

/// The finger (and placement) that stops `string` `above` semitones above the nut in
/// `position`, if that position reaches it.
pub(crate) fn stop_in_position(string: ViolinString, position: u8, above: u8) -> Option<Fingering> {
    let base = i32::from(position_offset(position));
    let above = i32::from(above);
    for finger in 1..=4u8 {
        for &placement in placements(finger) {
            let stop = base + i32::from(finger_offset(finger)) + i32::from(placement.semitones());
            if stop == above {
                return Some(Fingering::with_placement(
                    string, position, finger, placement,
                ));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physical::{HIGHEST_MIDI, LOWEST_MIDI, MAX_POSITION};
    use crate::Placement;

    #[test]
    fn the_e_string_needs_its_extension_for_the_top_notes() {
        // Without positions 11..=14 the E string stops at D#7.
        let top_at_10 = Fingering::with_placement(ViolinString::E, 10, 4, Placement::High);
        assert_eq!(top_at_10.midi(), 99);
        assert_eq!(Fingering::new(ViolinString::E, 14, 4).midi(), HIGHEST_MIDI);
        assert!(places_for(HIGHEST_MIDI)
            .iter()
            .all(|f| f.string == ViolinString::E && f.position > MAX_POSITION));
    }

    #[test]
    fn out_of_range_pitches_have_no_place() {
        assert!(places_for(54).is_empty());
        assert!(places_for(40).is_empty());
        assert!(places_for(107).is_empty());
        // A#7 is the model's last semitone (extended 4th finger in 14th position).
        assert_eq!(places_for(106).len(), 1);
    }

    #[test]
    fn places_are_ordered_by_string_then_position() {
        for midi in LOWEST_MIDI..=HIGHEST_MIDI {
            let places = places_for(midi);
            let keys: Vec<(ViolinString, u8)> =
                places.iter().map(|f| (f.string, f.position)).collect();
            let mut sorted = keys.clone();
            sorted.sort();
            sorted.dedup();
            assert_eq!(keys, sorted, "midi {midi}");
        }
    }
}
