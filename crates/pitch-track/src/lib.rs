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
//!
//! Labelled test audio comes from the `corpus` crate's renderers (a dev-dependency: the
//! tests, benches and comparison scripts use it; the library never does).
//!
//! ```
//! use pitch_track::{segment_notes, NoteConfig, PitchConfig, PitchTracker};
//! // One second of A4 (with two harmonics) at 22 050 Hz.
//! let sr = 22_050;
//! let samples: Vec<f32> = (0..sr)
//!     .map(|i| {
//!         let phase = std::f32::consts::TAU * 440.0 * i as f32 / sr as f32;
//!         0.5 * phase.sin() + 0.2 * (2.0 * phase).sin() + 0.1 * (3.0 * phase).sin()
//!     })
//!     .collect();
//! let tracker = PitchTracker::new(PitchConfig::default())?;
//! let track = tracker.track(&samples)?;
//! let notes = segment_notes(&track, &samples, sr as u32, &NoteConfig::default())?;
//! assert_eq!(notes.len(), 1);
//! assert_eq!(notes[0].midi, 69);
//! # Ok::<(), pitch_track::PitchError>(())
//! ```

mod config;
mod error;
mod hmm;
mod note_config;
mod notes;
mod novelty;
mod prior;
mod release;
mod split;
mod track;
mod yin;

pub mod eval;

pub use config::PitchConfig;
pub use error::{PitchError, Result};
pub use note_config::NoteConfig;
pub use notes::{segment_notes, segment_notes_with_novelty, Note};
pub use novelty::{onset_novelty, NoveltyConfig};
pub use release::{release_s, ReleaseConfig};
pub use split::{split_notes_at, start_notes_at};
pub use track::{hz_to_midi, midi_to_hz, PitchTrack, PitchTracker};
