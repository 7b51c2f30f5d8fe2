//! # fingering
//!
//! Left-hand fingering for the violinist skeleton (SPEC §6): for each note (a MIDI pitch),
//! choose the string, the position of the left hand and the finger that play it.
//!
//! * [`FingeringTable`] — for each pitch, the places that play it: the original design's
//!   table ([`FingeringTable::original`], embedded from `data/original_table.tsv`) or the
//!   [`physical`] model of the fingerboard ([`FingeringTable::physical`], every place for
//!   G3..=A7, exact to the semitone).
//! * [`GreedyPlanner`] — the original design's rule: stay in position while possible, else
//!   move to the nearest position (original table by default).
//! * [`OptimalPlanner`] — Viterbi over all places with tunable [`CostWeights`] for shifts,
//!   string crossings, high positions and open strings (physical table by default).
//! * [`LearnedPlanner`] — Viterbi over costs learned from ten violinists' fingerings (the
//!   TNUA dataset; [`LearnedParams`], trained by the `train` feature's `train` module),
//!   with where the passage is going as context ([`span`]).
//! * [`FingeringStyle`] — knobs for open strings, low or high positions and *sul* passages,
//!   and the double stops a line note must leave in reach ([`double_stop_place`]).
//!
//! A [`Fingering`] also tells where the left hand sits along the neck
//! ([`Fingering::hand_offset_semitones`]) and which pitch it plays ([`Fingering::midi`]).
//!
//! ```
//! use fingering::{FingeringPlanner, GreedyPlanner, OptimalPlanner, ViolinString};
//! // G major arpeggio G3 B3 D4 G4 B4 D5 G5.
//! let notes = [55, 59, 62, 67, 71, 74, 79];
//! let plan = OptimalPlanner::default().plan(&notes)?;
//! assert!(plan.iter().all(|f| f.position == 1));
//! assert_eq!(plan[2].string, ViolinString::D);
//! assert_eq!(plan[2].finger, 0); // open D
//! assert!(plan.iter().zip(&notes).all(|(f, &m)| f.midi() == m));
//!
//! let seed = GreedyPlanner::default().plan(&notes)?;
//! assert_eq!(seed.len(), notes.len());
//! assert!(OptimalPlanner::default().plan(&[40]).is_err()); // below the open G string
//! # Ok::<(), fingering::FingeringError>(())
//! ```

mod cost;
mod error;
mod fingering;
mod greedy;
mod learned;
mod learned_params;
mod optimal;
mod partner;
pub mod physical;
mod placement;
mod places;
mod planner;
pub mod span;
mod string;
mod style;
mod table;
#[cfg(feature = "train")]
pub mod train;
#[cfg(feature = "train")]
pub mod ytvf;

pub use cost::CostWeights;
pub use error::FingeringError;
pub use fingering::Fingering;
pub use greedy::GreedyPlanner;
pub use learned::{context, learned_places, LearnedPlanner, LEARNED_MAX_POSITION};
pub use learned_params::CONTEXTS;
pub use learned_params::{LearnedParams, LEARNED_PARAMS_TSV};
pub use optimal::OptimalPlanner;
pub use partner::{double_stop_place, partner_place};
pub use placement::Placement;
pub use places::places_for;
pub use planner::FingeringPlanner;
pub use span::SpanContext;
pub use string::ViolinString;
pub use style::{DoubleStopNote, FingeringStyle, SulPassage};
pub use table::{note_name_to_midi, FingeringTable, ORIGINAL_TABLE_TSV};

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
