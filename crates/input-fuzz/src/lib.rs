//! # input-fuzz
//!
//! Seeded mutation fuzzing of every parser that reads a user's file, on stable Rust: WAV,
//! FLAC, MP3 and Ogg decoding (then the analysis), MIDI (then the analysis and the motion),
//! OpenPose JSON frames (`pose-labels`, `render`), motion JSON/CSV/NPY (then a picture),
//! safetensors weights of the bowing, beat and arousal networks (then a forward pass), and
//! `analysis.json` / performance JSON (then the motion). BVH is only written, never read,
//! so it has no parser to fuzz.
//!
//! Each kind's seed is made by the project's own writers or taken from dsp-mel's audio
//! fixtures ([`seeds`]); mutants come from a seeded AFL-style mutator ([`mutate`]); a run
//! counts accepted and refused inputs, panics (caught, the mutant saved), the slowest
//! mutant, and the peak memory; a mutant that runs longer than the timeout ends the process
//! (exit 3) with the mutant saved. The `input-fuzz` binary runs every kind in its own child
//! process, so a signal (an abort, a stack overflow) or a hang of one kind is reported
//! instead of ending the run:
//!
//! ```sh
//! cargo run --release -p input-fuzz -- all --iterations 1000 --seed 1
//! ```

pub mod mutate;
pub mod runner;
pub mod seeds;
pub mod targets;

pub use runner::{fuzz_kind, FuzzSettings, KindReport};
pub use seeds::{seed_set, SeedSet};
pub use targets::Kind;
