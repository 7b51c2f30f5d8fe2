//! Where the other note of a double stop or chord goes, given the melody note's place.

use crate::fingering::Fingering;
use crate::string::ViolinString;
use crate::table::FingeringTable;

/// The place of a double-stop partner `midi` of `line` (already placed): on the neighbouring
/// string below (a lower note) or above (a higher one) — the next one out when that string
/// cannot play it — in the position nearest the line's; an open string when it is the
/// partner's pitch. `None` when no string but the line's plays it.
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
