//! Where a finger sits relative to its normal place: low, normal or high.

use serde::{Deserialize, Serialize};

/// Where a finger sits relative to its normal place in the position.
///
/// In a position whose first finger normally stops the string `b` semitones above the open
/// string, the fingers' normal places are `b`, `b + 2`, `b + 3`, `b + 5` (first finger,
/// whole step, half step, whole step: e.g. B C♯ D E on the A string in first position).
/// Each finger can also reach one neighbouring semitone, so that every semitone from `b - 1`
/// to `b + 6` is reached by exactly one finger:
///
/// | finger | reaches | placements |
/// |---|---|---|
/// | 1 | `b - 1`, `b` | low 1 (e.g. F♮ on the E string), normal |
/// | 2 | `b + 1`, `b + 2` | low 2 (C♮ on the A string), normal |
/// | 3 | `b + 3`, `b + 4` | normal, high 3 (D♯ on the A string) |
/// | 4 | `b + 5`, `b + 6` | normal, extended 4 (F♮ on the A string) |
///
/// Open strings are always [`Placement::Normal`].
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default, Serialize, Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Placement {
    /// A semitone below the finger's normal place (low 1, low 2).
    Low,
    /// The finger's normal place.
    #[default]
    Normal,
    /// A semitone above the finger's normal place (high 3, extended 4).
    High,
}

impl Placement {
    /// The semitone adjustment: -1, 0 or +1.
    pub const fn semitones(self) -> i8 {
        match self {
            Placement::Low => -1,
            Placement::Normal => 0,
            Placement::High => 1,
        }
    }

    /// `true` for [`Placement::Normal`] (used to keep it out of the JSON form).
    pub fn is_normal(&self) -> bool {
        *self == Placement::Normal
    }
}
