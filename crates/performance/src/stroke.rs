//! [`BowStroke`]: one stroke of the bow, its direction ([`BowDirection`]) and the string it
//! plays.

use fingering::ViolinString;

use crate::bowing::BowDirection;
use serde::{Deserialize, Serialize};

/// One bow stroke: from a bow change (or the first note after a rest) to the next, with its
/// direction and the string of its first note (`None` when the note has no fingering).
///
/// ```
/// use performance::{BowDirection, BowStroke};
/// let s = BowStroke { start_s: 0.5, end_s: 1.0, direction: BowDirection::Down, string: None };
/// assert_eq!(s.direction.reversed(), BowDirection::Up);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BowStroke {
    /// Onset of the stroke's first note, seconds.
    pub start_s: f64,
    /// End of the stroke's last note, seconds.
    pub end_s: f64,
    /// Down or up.
    pub direction: BowDirection,
    /// The string of the stroke's first note.
    pub string: Option<ViolinString>,
}
