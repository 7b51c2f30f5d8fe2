//! Helpers shared by this crate's integration tests.
#![allow(clippy::expect_used)]

use std::path::Path;

use corpus::build::{build_corpus, CorpusConfig};
use corpus::etude::EtudeConfig;

/// Builds a half-minute corpus of 10 s études (seed `seed`) in `dir`: train, validation and
/// test items, every label file, in a second or two.
pub fn build_tiny_corpus(dir: &Path, seed: u64) {
    let cfg = CorpusConfig {
        minutes: 0.5,
        seed,
        etude: EtudeConfig {
            target_s: 10.0,
            ..EtudeConfig::default()
        },
        ..CorpusConfig::default()
    };
    build_corpus(dir, &cfg, &|_, _| {}).expect("the tiny corpus builds");
}
