//! # corpus
//!
//! The synthetic violin corpus that trains and evaluates every model of violin-skeleton,
//! because URMP and DEAM cannot be downloaded here and their labels are noisy:
//!
//! 1. seeded procedural études ([`etude`]): keys and modes, scales, arpeggios, walks,
//!    sequences, repeated notes, rests; rhythms from whole notes to sixteenths, dotted and
//!    triplets; 2/4, 3/4, 4/4, 6/8; 50–170 bpm; slurs of 1–8 notes; pp–ff with hairpins;
//! 2. played into exact labels ([`timing`]): gentle rubato, bow changes (every note that
//!    does not continue a slur), beats, downbeats and an arousal proxy;
//! 3. rendered ([`render`]) by the built-in bowed-string synthesizer or a SoundFont, with
//!    seeded augmentation ([`augment`]);
//! 4. written to disk ([`layout`], [`manifest`]) with ground-truth motion from
//!    `motion-synth`, and summarised ([`stats`]).
//!
//! The many-violin corpus of real repertoire (`--renderer many`) plays written scores
//! ([`score`], [`repertoire`]) with human timing ([`perform::perform`]) and bowing as
//! violinists plan it (strokes hooked so that most bars start down-bow,
//! [`perform::hook_to_downbeats`]), through seven violin sources and simulated rooms.
//!
//! The trackers' tests and benches take their labelled audio from here ([`item::make_item`]
//! with [`render::BowedStringSynth`]) and score pitch against [`reference::reference_f0`].
//!
//! ```
//! use corpus::item::{make_item, RendererKind};
//! use corpus::render::BowedStringSynth;
//! let item = make_item(5, &Default::default(), &BowedStringSynth::default(), RendererKind::Builtin, false)?;
//! assert_eq!(item.motion.len(), item.performance.frame_count(30.0));
//! # Ok::<(), corpus::CorpusError>(())
//! ```

pub mod augment;
pub mod bow_weight;
pub mod build;
mod config;
pub mod double_stop;
mod error;
pub mod etude;
pub mod item;
pub mod layout;
pub mod manifest;
mod many;
pub mod melodies;
pub mod perform;
pub mod reference;
pub mod render;
pub mod repertoire;
pub mod room;
pub mod schedule;
pub mod score;
pub mod stats;
pub mod timing;
pub mod violins;

pub use error::CorpusError;
