//! The four strings of the violin.

use std::fmt;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// One of the violin's four strings, numbered as in the original design:
/// 1 = G3 (MIDI 55), 2 = D4 (62), 3 = A4 (69), 4 = E5 (76).
///
/// Serialises as its number (1..=4), as in the analysis file's `"string"` field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ViolinString {
    /// The lowest string, tuned to G3 (MIDI 55); string 1.
    G,
    /// The D string, D4 (MIDI 62); string 2.
    D,
    /// The A string, A4 (MIDI 69); string 3.
    A,
    /// The highest string, E5 (MIDI 76); string 4.
    E,
}

impl ViolinString {
    /// All four strings from the lowest (G) to the highest (E).
    pub const ALL: [ViolinString; 4] = [
        ViolinString::G,
        ViolinString::D,
        ViolinString::A,
        ViolinString::E,
    ];

    /// The string's number: 1 = G, 2 = D, 3 = A, 4 = E.
    pub const fn number(self) -> u8 {
        match self {
            ViolinString::G => 1,
            ViolinString::D => 2,
            ViolinString::A => 3,
            ViolinString::E => 4,
        }
    }

    /// The string numbered `number` (1..=4), or `None` for any other number.
    pub const fn from_number(number: u8) -> Option<ViolinString> {
        match number {
            1 => Some(ViolinString::G),
            2 => Some(ViolinString::D),
            3 => Some(ViolinString::A),
            4 => Some(ViolinString::E),
            _ => None,
        }
    }

    /// The MIDI pitch of the open string: 55, 62, 69 or 76.
    pub const fn open_midi(self) -> u8 {
        match self {
            ViolinString::G => 55,
            ViolinString::D => 62,
            ViolinString::A => 69,
            ViolinString::E => 76,
        }
    }

    /// The string's letter name: `"G"`, `"D"`, `"A"` or `"E"`.
    pub const fn name(self) -> &'static str {
        match self {
            ViolinString::G => "G",
            ViolinString::D => "D",
            ViolinString::A => "A",
            ViolinString::E => "E",
        }
    }
}

impl fmt::Display for ViolinString {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for ViolinString {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_u8(self.number())
    }
}

impl<'de> Deserialize<'de> for ViolinString {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let number = u8::deserialize(deserializer)?;
        ViolinString::from_number(number).ok_or_else(|| {
            serde::de::Error::custom(format!(
                "violin string number must be 1..=4 (G, D, A, E), got {number}"
            ))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_round_trip_and_open_pitches_are_fifths_apart() {
        for (i, s) in ViolinString::ALL.into_iter().enumerate() {
            assert_eq!(usize::from(s.number()), i + 1);
            assert_eq!(ViolinString::from_number(s.number()), Some(s));
        }
        assert_eq!(ViolinString::from_number(0), None);
        assert_eq!(ViolinString::from_number(5), None);
        let opens: Vec<u8> = ViolinString::ALL.iter().map(|s| s.open_midi()).collect();
        assert_eq!(opens, vec![55, 62, 69, 76]);
    }

    #[test]
    fn serde_uses_the_string_number() {
        assert_eq!(serde_json::to_string(&ViolinString::A).unwrap(), "3");
        let s: ViolinString = serde_json::from_str("1").unwrap();
        assert_eq!(s, ViolinString::G);
        assert!(serde_json::from_str::<ViolinString>("5").is_err());
        assert!(serde_json::from_str::<ViolinString>("0").is_err());
    }

    #[test]
    fn display_is_the_letter() {
        assert_eq!(ViolinString::E.to_string(), "E");
    }
}
