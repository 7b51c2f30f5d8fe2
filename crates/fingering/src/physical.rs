//! The physical fingerboard model: which (string, position, finger, placement) plays which
//! pitch, at semitone accuracy.
//!
//! # Geometry
//!
//! A position is named by where its first finger normally stops the string, in semitones
//! above the open string ([`position_offset`]); positions follow the steps of a major scale
//! from the open string, so the hand's place in semitones is:
//!
//! | position | half | 1 | 2 | 3 | 4 | 5 | 6 | 7 | 8 | 9 | 10 | 11 | 12 | 13 | 14 |
//! |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|
//! | first-finger offset | 1 | 2 | 4 | 5 | 7 | 9 | 10 | 12 | 14 | 16 | 17 | 19 | 21 | 22 | 24 |
//!
//! (from 1st position on, `12·⌊(p-1)/7⌋ + [2, 4, 5, 7, 9, 10, 12][(p-1) mod 7]`). Positions
//! whose first finger is commonly placed on either of two semitones (2nd = 3..4,
//! 5th = 8..9, 9th = 15..16, 12th = 20..21) take the higher one as normal and reach the
//! lower one with a low first finger.
//!
//! In a position with offset `b` the fingers normally stop `b`, `b + 2`, `b + 3`, `b + 5`
//! and each reaches one neighbouring semitone (see [`crate::Placement`]):
//! finger 1: `b - 1 ..= b`, finger 2: `b + 1 ..= b + 2`, finger 3: `b + 3 ..= b + 4`,
//! finger 4: `b + 5 ..= b + 6`. Every semitone from `b - 1` to `b + 6` is thus reached by
//! exactly one finger, so a (string, position) plays a pitch with at most one finger.
//! A stopped note is at least one semitone above the nut (no low 1 in half position).
//!
//! The G, D and A strings have the half position and positions 1..=10. Positions 1..=10 on
//! the E string reach only D#7 (MIDI 99), so the E string is extended to the 14th position
//! (first finger on E7, 4th finger on A7 = MIDI 105). An open string can be played from
//! any position of its string: the hand stays where it is.
//!
//! The model's range is therefore G3 (MIDI 55, open G) to A#7 (106); the physical table
//! ([`crate::FingeringTable::physical`]) lists G3..=A7 (55..=105).

use crate::placement::Placement;
use crate::string::ViolinString;

/// The half position's number.
pub const HALF_POSITION: u8 = 0;
/// The highest position on the G, D and A strings.
pub const MAX_POSITION: u8 = 10;
/// The highest position on the E string (extended so that A7 has a place).
pub const MAX_POSITION_E_STRING: u8 = 14;
/// The lowest pitch the physical table lists (G3, the open G string).
pub const LOWEST_MIDI: u8 = 55;
/// The highest pitch the physical table lists (A7).
pub const HIGHEST_MIDI: u8 = 105;

/// First-finger offsets of positions 1..=7 within an octave.
const OCTAVE_PATTERN: [u16; 7] = [2, 4, 5, 7, 9, 10, 12];
/// Normal offset of each finger from the first finger's place (index = finger, 0 unused).
const FINGER_OFFSET: [u8; 5] = [0, 0, 2, 3, 5];
const PLACEMENTS_LOW: [Placement; 2] = [Placement::Normal, Placement::Low];
const PLACEMENTS_HIGH: [Placement; 2] = [Placement::Normal, Placement::High];
const PLACEMENTS_OPEN: [Placement; 1] = [Placement::Normal];

/// Semitones above the open string of `position`'s first-finger normal place (also where
/// the hand sits, [`crate::Fingering::hand_offset_semitones`]): 1 for the half position, then
/// 2, 4, 5, 7, 9, 10, 12, 14, 16, 17, 19, 21, 22, 24 for positions 1..=14. Defined (by the
/// same octave pattern) for every `u8`.
pub const fn position_offset(position: u8) -> u16 {
    if position == HALF_POSITION {
        return 1;
    }
    let step = (position - 1) as usize;
    12 * (step / 7) as u16 + OCTAVE_PATTERN[step % 7]
}

/// The normal offset of `finger` (1..=4) from the first finger's place: 0, 2, 3, 5
/// (0 for the open string and for fingers above 4).
pub const fn finger_offset(finger: u8) -> u8 {
    if finger as usize >= FINGER_OFFSET.len() {
        0
    } else {
        FINGER_OFFSET[finger as usize]
    }
}

/// The placements `finger` can take: normal and low for fingers 1 and 2, normal and high
/// for fingers 3 and 4, normal only for the open string (and for fingers above 4).
pub const fn placements(finger: u8) -> &'static [Placement] {
    match finger {
        1 | 2 => &PLACEMENTS_LOW,
        3 | 4 => &PLACEMENTS_HIGH,
        _ => &PLACEMENTS_OPEN,
    }
}

/// The highest position on `string`: 10, or 14 on the E string.
pub const fn max_position(string: ViolinString) -> u8 {
    match string {
        ViolinString::E => MAX_POSITION_E_STRING,
        _ => MAX_POSITION,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Fingering;

    #[test]
    fn position_offsets_match_the_documented_geometry() {
        let offsets: Vec<u16> = (0..=14).map(position_offset).collect();
        assert_eq!(
            offsets,
            vec![1, 2, 4, 5, 7, 9, 10, 12, 14, 16, 17, 19, 21, 22, 24]
        );
        // 255 = 1 + 7·36 + 2: the third step of the 37th octave.
        assert_eq!(position_offset(255), 12 * 36 + 5);
    }

    #[test]
    fn each_finger_reaches_two_adjacent_semitones_covering_b_minus_1_to_b_plus_6() {
        for position in 1..=10u8 {
            let b = i32::from(position_offset(position));
            let mut reached = Vec::new();
            for finger in 1..=4u8 {
                for &p in placements(finger) {
                    let f = Fingering::with_placement(ViolinString::A, position, finger, p);
                    reached.push(i32::from(f.semitones_above_open()) - b);
                }
            }
            reached.sort_unstable();
            assert_eq!(reached, (-1..=6).collect::<Vec<_>>(), "position {position}");
        }
    }
}
