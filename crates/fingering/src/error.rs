//! Errors of the fingering crate.

/// What can go wrong when planning fingerings or reading a fingering table.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FingeringError {
    /// The note at `index` has no place in the planner's table (e.g. below the open G
    /// string, MIDI 55, or above the table's highest note).
    #[error(
        "note {index} (MIDI {midi}) cannot be played: the fingering table has no place for it"
    )]
    UnplayablePitch {
        /// Index of the note in the planner's input.
        index: usize,
        /// Its MIDI pitch.
        midi: u8,
    },
    /// A fingering table in TSV form could not be read.
    #[error("fingering table, line {line}: {reason}")]
    InvalidTable {
        /// 1-based line number in the TSV text.
        line: usize,
        /// What is wrong with the line.
        reason: String,
    },
    /// A training dataset file or directory could not be read (feature `train`).
    #[error("{path}: {reason}")]
    Dataset {
        /// The file or directory.
        path: String,
        /// What is wrong.
        reason: String,
    },
}
