//! Labelled recordings in memory (training only; `violin-train` reads them from disk).

use ndarray::{Array2, ArrayView2};

use crate::error::Result;
use crate::features::frame_features;

/// One recording: its input frames and its beats.
#[derive(Debug, Clone)]
pub struct Recording {
    /// A name for reports.
    pub name: String,
    /// Input frames ([`crate::features::frame_features`] of the 30 fps mel).
    pub features: Array2<f32>,
    /// Beat times in seconds (downbeats included).
    pub beats_s: Vec<f64>,
    /// Downbeat times in seconds.
    pub downbeats_s: Vec<f64>,
}

impl Recording {
    /// A recording from its mel dB spectrogram and labels.
    pub fn from_mel(
        name: String,
        mel_db: ArrayView2<f32>,
        beats_s: Vec<f64>,
        downbeats_s: Vec<f64>,
    ) -> Result<Self> {
        Ok(Self {
            name,
            features: frame_features(mel_db)?,
            beats_s,
            downbeats_s,
        })
    }

    /// Frames.
    pub fn frames(&self) -> usize {
        self.features.nrows()
    }
}

/// Recordings by split (test recordings are never read by training).
#[derive(Debug, Clone, Default)]
pub struct Splits {
    /// Training recordings.
    pub train: Vec<Recording>,
    /// Validation recordings (early stopping).
    pub val: Vec<Recording>,
}
