//! The planner interface: one place per note.

use crate::error::FingeringError;
use crate::fingering::Fingering;

/// Chooses one [`Fingering`] per note.
pub trait FingeringPlanner {
    /// Plans `midi` (one MIDI pitch per note, in order) and returns one place per note;
    /// empty input gives an empty plan. A pitch that no place of the planner's table plays
    /// gives [`FingeringError::UnplayablePitch`] with its index.
    fn plan(&self, midi: &[u8]) -> Result<Vec<Fingering>, FingeringError>;
}
