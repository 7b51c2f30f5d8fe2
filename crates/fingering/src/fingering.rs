//! One place on the fingerboard: string, position, finger (and the finger's placement).

use serde::{Deserialize, Serialize};

use crate::physical;
use crate::placement::Placement;
use crate::string::ViolinString;

/// A place that plays a note: which string, which position the left hand is in, which
/// finger stops the string (0 = open string) and where that finger sits ([`Placement`]).
///
/// Serialises as `{"string": 1..=4, "position": n, "finger": n}`; a low or high finger adds
/// `"placement": "low" | "high"` (a normal placement is left out, and is the default when
/// reading).
///
/// `position` is 0 for the half position, 1..=10 for the positions on every string, and
/// 11..=14 on the E string only (the physical model extends the E string so that A7 can be
/// played). An open string keeps the position the hand was in.
///
/// ```
/// use fingering::{Fingering, ViolinString};
/// let b4 = Fingering::new(ViolinString::A, 1, 1);
/// assert_eq!(b4.midi(), 71);
/// assert_eq!(b4.hand_offset_semitones(), 2.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Fingering {
    /// The string that sounds.
    pub string: ViolinString,
    /// The left hand's position: 0 = half position, 1..=10 (11..=14 on the E string).
    pub position: u8,
    /// The finger that stops the string: 0 = open string, 1..=4 = index to little finger.
    pub finger: u8,
    /// Where the finger sits relative to its normal place in the position.
    #[serde(default, skip_serializing_if = "Placement::is_normal")]
    pub placement: Placement,
}

impl Fingering {
    /// A finger in its normal place (`finger` 0 is the open string).
    pub const fn new(string: ViolinString, position: u8, finger: u8) -> Fingering {
        Fingering {
            string,
            position,
            finger,
            placement: Placement::Normal,
        }
    }

    /// A finger placed low, normal or high.
    pub const fn with_placement(
        string: ViolinString,
        position: u8,
        finger: u8,
        placement: Placement,
    ) -> Fingering {
        Fingering {
            string,
            position,
            finger,
            placement,
        }
    }

    /// The open `string`, played while the hand stays in `position`.
    pub const fn open(string: ViolinString, position: u8) -> Fingering {
        Fingering::new(string, position, 0)
    }

    /// `true` for an open string (finger 0).
    pub const fn is_open(&self) -> bool {
        self.finger == 0
    }

    /// Semitones above the open string at which the string is stopped (0 when open), under
    /// the physical model: the position's first-finger offset (see
    /// [`physical::position_offset`]) plus the finger's normal offset (0, 2, 3, 5 for
    /// fingers 1..=4) plus the placement's ±1. Fingers above 4 count as a 4th finger.
    pub fn semitones_above_open(&self) -> u16 {
        if self.finger == 0 {
            return 0;
        }
        let base = i32::from(physical::position_offset(self.position));
        let finger = i32::from(physical::finger_offset(self.finger.min(4)));
        let stop = base + finger + i32::from(self.placement.semitones());
        u16::try_from(stop.max(0)).unwrap_or(u16::MAX)
    }

    /// The MIDI pitch this place plays under the physical model (saturating at 255 for
    /// places far beyond any fingerboard).
    pub fn midi(&self) -> u8 {
        let pitch = u16::from(self.string.open_midi()) + self.semitones_above_open();
        u8::try_from(pitch).unwrap_or(u8::MAX)
    }

    /// Where the left hand sits along the neck, in semitones from the nut: the offset of the
    /// position's first-finger normal place ([`physical::position_offset`]), e.g. 1 for the
    /// half position, 2 for first, 5 for third, 12 for seventh.
    ///
    /// It depends on the position only, not on the string, the finger or its placement, so
    /// an open string (which keeps the position the hand was in) reports where the hand
    /// already is and the wrist does not move. Motion synthesis places the left wrist from it.
    pub fn hand_offset_semitones(&self) -> f32 {
        f32::from(physical::position_offset(self.position))
    }

    /// `true` if the physical model has this place: a position that exists on the string,
    /// a finger 0..=4, and a placement that finger can take (an open string is normal;
    /// see [`Placement`]), stopping the string at least one semitone above the nut.
    pub fn is_physical(&self) -> bool {
        if self.position > physical::max_position(self.string) || self.finger > 4 {
            return false;
        }
        if self.finger == 0 {
            return self.placement == Placement::Normal;
        }
        physical::placements(self.finger).contains(&self.placement)
            && self.semitones_above_open() >= 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_position_on_the_a_string() {
        let a = ViolinString::A;
        assert_eq!(Fingering::open(a, 1).midi(), 69);
        assert_eq!(Fingering::new(a, 1, 1).midi(), 71); // B4
        assert_eq!(
            Fingering::with_placement(a, 1, 2, Placement::Low).midi(),
            72
        ); // C5
        assert_eq!(Fingering::new(a, 1, 2).midi(), 73); // C#5
        assert_eq!(Fingering::new(a, 1, 3).midi(), 74); // D5
        assert_eq!(Fingering::new(a, 1, 4).midi(), 76); // E5
        assert_eq!(
            Fingering::with_placement(a, 1, 4, Placement::High).midi(),
            77
        ); // F5
    }

    #[test]
    fn hand_offset_follows_the_position_and_ignores_open_strings() {
        assert_eq!(
            Fingering::new(ViolinString::G, 0, 1).hand_offset_semitones(),
            1.0
        );
        assert_eq!(
            Fingering::open(ViolinString::D, 3).hand_offset_semitones(),
            5.0
        );
        assert_eq!(
            Fingering::new(ViolinString::E, 7, 4).hand_offset_semitones(),
            12.0
        );
        assert_eq!(
            Fingering::open(ViolinString::E, 7).hand_offset_semitones(),
            Fingering::new(ViolinString::G, 7, 2).hand_offset_semitones()
        );
    }

    #[test]
    fn serde_form_is_numbers_and_skips_a_normal_placement() {
        let f = Fingering::new(ViolinString::D, 1, 3);
        assert_eq!(
            serde_json::to_string(&f).unwrap(),
            r#"{"string":2,"position":1,"finger":3}"#
        );
        let back: Fingering =
            serde_json::from_str(r#"{"string":2,"position":1,"finger":3}"#).unwrap();
        assert_eq!(back, f);
        let low = Fingering::with_placement(ViolinString::E, 1, 1, Placement::Low);
        let text = serde_json::to_string(&low).unwrap();
        assert_eq!(
            text,
            r#"{"string":4,"position":1,"finger":1,"placement":"low"}"#
        );
        assert_eq!(serde_json::from_str::<Fingering>(&text).unwrap(), low);
    }

    #[test]
    fn physical_validity() {
        assert!(Fingering::new(ViolinString::E, 14, 4).is_physical());
        assert!(!Fingering::new(ViolinString::A, 11, 1).is_physical());
        assert!(!Fingering::new(ViolinString::A, 1, 5).is_physical());
        assert!(!Fingering::with_placement(ViolinString::A, 1, 3, Placement::Low).is_physical());
        assert!(!Fingering::with_placement(ViolinString::A, 1, 0, Placement::High).is_physical());
        // Low 1 in half position would sit on the nut.
        assert!(!Fingering::with_placement(ViolinString::A, 0, 1, Placement::Low).is_physical());
    }

    #[test]
    fn absurd_fields_saturate_instead_of_overflowing() {
        let f = Fingering::new(ViolinString::E, 255, 9);
        assert_eq!(f.midi(), 255);
        assert!(f.hand_offset_semitones() > 100.0);
    }
}
