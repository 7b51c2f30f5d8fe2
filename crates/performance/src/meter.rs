//! [`Meter`]: how many beats a bar has and how each beat divides.

use serde::{Deserialize, Serialize};

/// Beats per bar and subdivisions per beat: 4/4 = `{4, 2}`, 3/4 = `{3, 2}`, 2/4 = `{2, 2}`,
/// 6/8 = `{2, 3}` (two dotted-quarter beats of three eighths).
///
/// ```
/// assert_eq!(performance::Meter::SIX_EIGHT.beats_per_bar, 2);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Meter {
    /// Beats per bar.
    pub beats_per_bar: u8,
    /// Subdivisions per beat: 2 (simple metre) or 3 (compound).
    pub subdivisions: u8,
}

impl Meter {
    /// 2/4.
    pub const TWO_FOUR: Meter = Meter {
        beats_per_bar: 2,
        subdivisions: 2,
    };
    /// 3/4.
    pub const THREE_FOUR: Meter = Meter {
        beats_per_bar: 3,
        subdivisions: 2,
    };
    /// 4/4.
    pub const FOUR_FOUR: Meter = Meter {
        beats_per_bar: 4,
        subdivisions: 2,
    };
    /// 6/8 as two beats of three eighths.
    pub const SIX_EIGHT: Meter = Meter {
        beats_per_bar: 2,
        subdivisions: 3,
    };
}
