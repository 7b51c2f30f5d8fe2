//! A seeded synthetic violin with exact labels, for tests, benches and evaluation.
//!
//! [`render()`] turns a [`SynthConfig`] into a [`SynthPiece`]: audio plus the ground truth
//! (notes, f0 per sample, beats and downbeats). The score ([`score`]) is a random walk in a
//! major key over a chord per bar, in a metre with accented downbeats and a rubato tempo
//! curve; the sound ([`mod@render`]) is additive: harmonics with a bowed-string spectrum
//! (1/k with body resonances), vibrato (±30–50 cents at 5–7 Hz) that starts after the onset,
//! bow-noise bursts and an amplitude dip at bow changes, slurred note changes with a short
//! glide and no re-attack, repeated notes, rests, and a faint noise floor.
//! Everything random comes from [`SynthConfig::seed`], so a config always renders the same
//! samples.
//!
//! ```
//! use pitch_track::synth::{render, SynthConfig, TimeSignature};
//! let piece = render(&SynthConfig { seed: 7, bars: 2, tempo_bpm: 90.0, time_signature: TimeSignature::THREE_FOUR, ..SynthConfig::default() })?;
//! assert_eq!(piece.beats_s.len(), 6);
//! assert_eq!(piece.downbeats_s.len(), 2);
//! assert!(piece.notes.iter().all(|n| n.offset_s > n.onset_s));
//! # Ok::<(), pitch_track::PitchError>(())
//! ```

pub mod render;
pub mod score;

mod piece;

pub use piece::{Rng, SynthConfig, SynthNote, SynthPiece, TimeSignature};
pub use render::render;
pub use score::{compose, Score};
