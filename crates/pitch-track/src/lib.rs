//! # pitch-track
//!
//! Monophonic f0 tracking and note segmentation for solo violin (SPEC §6).
//!
//! * [`PitchTracker`] — pYIN (Mauch & Dixon 2014) as `librosa.pyin` computes it: the YIN
//!   cumulative-mean-normalised difference from an FFT autocorrelation (a real FFT planned
//!   once by `dsp_mel::fft`, frames in parallel), probabilistic candidates under a beta prior
//!   over thresholds, and a Viterbi decode over pitch bins × {voiced, unvoiced} with a
//!   limited pitch jump per frame.
//!   Output: [`PitchTrack`] (f0 in Hz, NaN where unvoiced, and the voiced probability), which
//!   [`PitchTrack::resample_to_fps`] puts on the skeleton's 30 fps grid.
//! * [`segment_notes`] — stable-pitch segments of the f0 path, split at onsets inside a
//!   constant pitch, robust to vibrato and slurred glides → [`Note`]s.
//! * [`eval`] — mir_eval-compatible scores: raw pitch accuracy, voicing recall and false
//!   alarm, note-onset precision/recall/F.
//! * [`synth`] — a seeded, labelled synthetic violin (vibrato, bow-change noise, slurs,
//!   repeated notes, rests, metre and accents) for tests, benches and evaluation.
//!
//! ```
//! use pitch_track::{segment_notes, NoteConfig, PitchConfig, PitchTracker};
//! use pitch_track::synth::{render, SynthConfig};
//! let piece = render(&SynthConfig { bars: 2, ..SynthConfig::default() })?;
//! let tracker = PitchTracker::new(PitchConfig::default())?;
//! let track = tracker.track(&piece.samples)?;
//! let notes = segment_notes(&track, &piece.samples, piece.sample_rate_hz, &NoteConfig::default())?;
//! assert!(!notes.is_empty());
//! # Ok::<(), pitch_track::PitchError>(())
//! ```

mod config;
mod error;
mod hmm;
mod note_config;
mod notes;
mod novelty;
mod prior;
mod split;
mod track;
mod yin;

pub mod eval;
pub mod synth;

pub use config::PitchConfig;
pub use error::{PitchError, Result};
pub use note_config::NoteConfig;
pub use notes::{segment_notes, segment_notes_with_novelty, Note};
pub use novelty::{onset_novelty, NoveltyConfig};
pub use split::{split_notes_at, start_notes_at};
pub use track::{hz_to_midi, midi_to_hz, PitchTrack, PitchTracker};
