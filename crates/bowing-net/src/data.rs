//! Labelled recordings in memory, what training and evaluation take: a recording's 30 fps
//! mel spectrogram with its bow-change, note-onset and slurred-note-change frames, its
//! strokes and the string of every frame when known, and the
//! recordings by split. Loading them from the synthetic corpus or a URMP folder is
//! `violin-train`'s job.

use ndarray::Array2;

/// One labelled recording.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// A name for reports (the item folder or track file).
    pub name: String,
    /// The source kind: `builtin`, `soundfont` or `urmp`.
    pub group: String,
    /// 30 fps × 128 mel dB.
    pub mel_db: Array2<f32>,
    /// Bow-change frames (sorted).
    pub changes: Vec<usize>,
    /// Note-onset frames (sorted; empty when unknown).
    pub onsets: Vec<usize>,
    /// Note changes inside a slur (an onset that is not a bow change).
    pub slurred: Vec<usize>,
    /// Bow strokes with direction and string, seconds (empty when unknown).
    pub strokes: Vec<performance::BowStroke>,
    /// The string of the sounding note at every frame: 0 = none or unknown, 1–4 = G, D, A,
    /// E (empty when unknown).
    pub strings: Vec<u8>,
}

/// Recordings by split.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Splits {
    /// Training recordings.
    pub train: Vec<Recording>,
    /// Validation recordings (early stopping, decoder tuning).
    pub val: Vec<Recording>,
    /// Test recordings (reported figures).
    pub test: Vec<Recording>,
}
