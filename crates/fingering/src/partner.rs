//! Where the other note of a double stop or chord goes, given the melody note's place.

use crate::fingering::Fingering;
use crate::physical::max_position;
use crate::places::stop_in_position;
use crate::string::ViolinString;
use crate::table::FingeringTable;

/// The place of a double-stop partner `midi` that the hand holding `line` can play with it:
/// on the neighbouring string (below for a lower note or a unison, above for a higher one),
/// open or stopped within one position of the line's (the same position first, then the one
/// below, then the one above). `None` when that string cannot play the partner in reach, for
/// instance G4 under E5 on the open E string: the A string starts at A4, so the line has to
/// move to the A string for the sixth to be playable.
///
/// Where it gives a place, [`partner_place`] gives the same one.
///
/// ```
/// use fingering::{double_stop_place, Fingering, ViolinString};
/// let open_e = Fingering::open(ViolinString::E, 1);
/// assert_eq!(double_stop_place(&open_e, 67), None); // G4 is not on the A string
/// // E5 on the A string in 3rd position (2nd finger): G4 on the D string, 1st finger.
/// let e5 = Fingering::new(ViolinString::A, 3, 2);
/// let g4 = double_stop_place(&e5, 67).unwrap();
/// assert_eq!((g4.string, g4.position, g4.finger), (ViolinString::D, 3, 1));
/// ```
pub fn double_stop_place(line: &Fingering, midi: u8) -> Option<Fingering> {
    let here = line.string.number();
    let number = if midi <= line.midi() {
        here.checked_sub(1)?
    } else {
        here + 1
    };
    let string = ViolinString::from_number(number)?;
    let above = midi.checked_sub(string.open_midi())?;
    if above == 0 {
        return Some(Fingering::open(string, line.position));
    }
    let near = [
        Some(line.position),
        line.position.checked_sub(1),
        line.position.checked_add(1),
    ];
    near.into_iter()
        .flatten()
        .filter(|&p| p <= max_position(string))
        .find_map(|p| stop_in_position(string, p, above))
}

/// The place of a double-stop partner `midi` of `line` (already placed): on the neighbouring
/// string below (a lower note) or above (a higher one) — the next one out when that string
/// cannot play it — in the position nearest the line's; an open string when it is the
/// partner's pitch. `None` when no string but the line's plays it. Unlike
/// [`double_stop_place`] it always finds a place when another string has one, in reach of
/// the hand or not.
///
/// ```
/// use fingering::{partner_place, Fingering, ViolinString};
/// // A5 on the E string (first position, fourth finger) over D5: on the A string.
/// let line = Fingering::new(ViolinString::E, 1, 4);
/// let d5 = partner_place(&line, 74).unwrap();
/// assert_eq!((d5.string, d5.position), (ViolinString::A, 1));
/// // An open A under it is the open string.
/// assert!(partner_place(&line, 69).unwrap().is_open());
/// ```
pub fn partner_place(line: &Fingering, midi: u8) -> Option<Fingering> {
    let table = FingeringTable::physical();
    let places = table.places(midi);
    let here = i32::from(line.string.number());
    let dir = if midi < line.midi() { -1 } else { 1 };
    for step in 1..=3 {
        let Some(string) = u8::try_from(here + dir * step)
            .ok()
            .and_then(ViolinString::from_number)
        else {
            break;
        };
        let best = places
            .iter()
            .filter(|f| f.string == string)
            .min_by_key(|f| (!f.is_open(), f.position.abs_diff(line.position)));
        if let Some(&f) = best {
            return Some(if f.is_open() {
                Fingering::open(string, line.position)
            } else {
                f
            });
        }
    }
    places
        .iter()
        .filter(|f| f.string != line.string)
        .min_by_key(|f| f.position.abs_diff(line.position))
        .copied()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physical::{HIGHEST_MIDI, LOWEST_MIDI};
    use crate::places::places_for;

    #[test]
    fn an_in_reach_place_is_the_one_partner_place_gives() {
        let mut found = 0;
        for line_midi in LOWEST_MIDI..=HIGHEST_MIDI {
            for line in places_for(line_midi) {
                for midi in LOWEST_MIDI..=HIGHEST_MIDI {
                    if midi == line_midi {
                        continue;
                    }
                    let Some(place) = double_stop_place(&line, midi) else {
                        continue;
                    };
                    found += 1;
                    assert_eq!(place.midi(), midi);
                    assert_eq!(place.string.number().abs_diff(line.string.number()), 1);
                    assert!(place.is_open() || place.position.abs_diff(line.position) <= 1);
                    assert_eq!(partner_place(&line, midi), Some(place), "{line:?} {midi}");
                }
            }
        }
        assert!(found > 5_000, "{found}"); // every in-reach pair was compared
    }

    #[test]
    fn out_of_reach_partners_have_no_double_stop_place() {
        // Nothing below the G string, nothing above the E string.
        assert_eq!(
            double_stop_place(&Fingering::new(ViolinString::G, 1, 1), 55),
            None
        );
        assert_eq!(
            double_stop_place(&Fingering::new(ViolinString::E, 1, 1), 90),
            None
        );
        // C5 over D4 in first position: the A string's C5 is two positions from 3rd.
        let d4_third = Fingering::new(ViolinString::G, 3, 2);
        assert_eq!(d4_third.midi(), 62);
        assert_eq!(double_stop_place(&d4_third, 81), None);
    }
}
