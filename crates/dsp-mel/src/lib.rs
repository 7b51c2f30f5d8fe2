//! # dsp-mel
//!
//! The signal-processing ground of violin-skeleton: decode audio files to mono
//! ([`load_audio`]), resample ([`resample`]), compute mel spectrograms that match
//! `librosa.feature.melspectrogram` ([`MelSpectrogram`], [`MelConfig`]), convert to dB
//! ([`power_to_db`]), and the scipy-equivalent [`filters`] used on pose tracks. It is the
//! workspace's only FFT planner: [`fft`] hands out planned transforms (complex, real, and
//! two real frames per complex FFT), [`Stft`] is the one short-time power spectrum.
//!
//! ```
//! use dsp_mel::{Audio, MelConfig, MelSpectrogram, DbConfig};
//! let tone: Vec<f32> = (0..22_050).map(|i| (i as f32 * 0.1).sin()).collect();
//! let audio = Audio::new(tone, 22_050)?;
//! let mel = MelSpectrogram::new(MelConfig::bowing().at_sample_rate(audio.sample_rate_hz()))?;
//! let db = mel.compute_db(audio.samples(), &DbConfig::default())?;
//! assert_eq!(db.ncols(), 128);
//! # Ok::<(), dsp_mel::DspError>(())
//! ```

mod audio;
mod config;
mod db;
mod error;
mod filterbank;
mod guard;
mod mel;
mod pair_fft;
mod resample;
mod stft;
mod stream;

pub mod fft;
pub mod filters;

pub use audio::{load_audio, load_audio_bytes, AnalysisRate, Audio, DEFAULT_ANALYSIS_RATE_HZ};
pub use config::{Hop, MelConfig, MelNorm, MelScale, Window};
pub use db::{power_to_db, DbConfig, DbRef};
pub use error::{DspError, Result};
pub use filterbank::{hz_to_mel, mel_filterbank, mel_frequencies, mel_to_hz};
pub use guard::inside_decoder_guard;
pub use mel::{pool_frames, MelSpectrogram};
pub use resample::{load_audio_at, resample};
pub use stft::{Stft, StftFloat};
pub use stream::{AudioReader, MAX_FILE_RATE_HZ, MIN_FILE_RATE_HZ};

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
