//! # beat-track
//!
//! Onsets, tempo, beats, metre and downbeats of a solo recording (SPEC §7), with librosa's
//! semantics where librosa has the function:
//!
//! * [`OnsetStrength`] — `librosa.onset.onset_strength` (log-mel spectral flux), mean and
//!   median over bands in one pass; [`onset_detect`] / [`peak_pick`] — `onset_detect`.
//! * [`estimate_tempo`] — `librosa.feature.tempo` (mean autocorrelation tempogram with a
//!   log-normal prior around 120 bpm), the mean taken over every fourth 8 s window
//!   ([`TempoConfig::frame_stride`]; [`mean_tempogram`] keeps librosa's every window).
//! * [`track_beats`] — `librosa.beat.beat_track`'s dynamic programme (Ellis 2007,
//!   tightness 100), which follows tempo drift (rubato) beat by beat;
//!   [`track_beats_with`] adds evidence to the onset strength ([`BeatTracker`] adds where
//!   long notes start, [`BeatConfig::note_salience`]).
//! * [`level`] — which tempo to track: every strong tempogram peak is tracked and the beat
//!   sequences are scored on how notes, onsets and bow changes fall on them (librosa takes
//!   the prior-weighted maximum, which on violin music is often double or 3/2 the beat).
//! * [`estimate_meter`] — beats per bar (2, 3, 4 or 6/8) and bar phase from accents and,
//!   when given ([`BarEvidence`]), notes from `pitch-track` and bow changes (see [`meter`]).
//! * [`BeatTracker`] — all of it in one call → [`BeatAnalysis`].
//! * [`bar_pointer`] — beats, downbeats, metre and per-beat tempo decoded from learned
//!   beat/downbeat activations (beat-net's) with a bar-pointer HMM, as madmom's
//!   `DBNDownBeatTrackingProcessor`.
//! * [`eval`] — beat/downbeat F-measure as mir_eval (the matcher is `performance`'s).
//!
//! ```
//! use beat_track::{BeatConfig, BeatTracker};
//! // 12 s of a plucked 660 Hz tone on every beat at 120 bpm, at 22 050 Hz.
//! let sr = 22_050;
//! let beats_s: Vec<f64> = (1..24).map(|k| 0.5 * f64::from(k)).collect();
//! let mut samples = vec![0.0f32; 12 * sr];
//! for &b in &beats_s {
//!     let start = (b * sr as f64) as usize;
//!     for (i, s) in samples[start..start + sr / 5].iter_mut().enumerate() {
//!         let t = i as f32 / sr as f32;
//!         *s += 0.5 * (-t / 0.05).exp() * (std::f32::consts::TAU * 660.0 * t).sin();
//!     }
//! }
//! let analysis = BeatTracker::new(BeatConfig::default())?.track(&samples, None)?;
//! let f = beat_track::eval::beat_prf(&beats_s, &analysis.beats_s, 0.07).f_measure;
//! assert!(f > 0.8, "{f}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Labelled violin audio for the tests and benches comes from the `corpus` crate's renderers
//! (a dev-dependency; the library never uses it).

mod bar_features;
pub mod bar_pointer;
mod bar_pointer_config;
mod bar_state;
mod beat_config;
mod dp;
mod error;
pub mod eval;
pub mod level;
pub mod meter;
mod meter_config;
mod onset;
mod peaks;
mod spectrum;
mod subdivision;
mod tempo;
mod tracker;

pub use bar_features::{BarEvidence, BeatFeatures};
pub use beat_config::{BeatAnalysis, BeatConfig};
pub use dp::{track_beats, track_beats_with};
pub use error::{BeatError, Result};
pub use level::{LevelCandidate, LevelConfig, LevelFeatures, LevelWeights, TempogramPeak};
pub use meter::{estimate_meter, Meter, MeterConfig, MeterEstimate};
pub use onset::{Aggregate, OnsetConfig, OnsetEnvelope, OnsetStrength};
pub use peaks::{onset_detect, peak_pick, PeakPick};
pub use subdivision::subdivisions;
pub use tempo::{estimate_tempo, mean_tempogram, mean_tempogram_strided, TempoConfig};
pub use tracker::BeatTracker;
