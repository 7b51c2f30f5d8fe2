//! Training data in memory: pairs of mel frames and normalised joint positions, at 30 fps,
//! split into training, validation and test sets. Reading them from the synthetic corpus or
//! URMP + OpenPose is `violin-train`'s job.

use ndarray::Array2;
use skeleton::Motion;

use crate::error::{GruError, Result};
use crate::features::{align, mel_frames};
use crate::norm::VideoNorm;

/// One recording: its mel frames and its joints, aligned frame by frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Sequence {
    /// A name for messages (the item or audio file).
    pub name: String,
    /// Mel frames in dB, `(frames, 128)`.
    pub mel_db: Array2<f32>,
    /// Joints normalised with `video`, `(frames, 20)` (x, y per joint).
    pub joints: Array2<f32>,
    /// The video's centre and torso length (pixels).
    pub video: VideoNorm,
    /// The video's image size, when known.
    pub image_size: Option<(u32, u32)>,
}

impl Sequence {
    /// Pairs `audio` with `motion` (30 fps): mel frames, per-video normalisation, truncation
    /// to the shorter of the two.
    pub fn from_audio_and_motion(
        name: String,
        audio: &dsp_mel::Audio,
        motion: &Motion,
    ) -> Result<Self> {
        if (motion.fps() - crate::features::FPS).abs() > 0.5 {
            return Err(GruError::Data {
                path: name.into(),
                reason: format!(
                    "the motion runs at {} fps; Method 1 needs 30 fps (resample the video's poses)",
                    motion.fps()
                ),
            });
        }
        let video = VideoNorm::of(motion)?;
        let (mel_db, joints) = align(mel_frames(audio)?, video.normalize(motion));
        if mel_db.nrows() == 0 {
            return Err(GruError::Empty(name));
        }
        Ok(Self {
            name,
            mel_db,
            joints,
            video,
            image_size: motion.image_size(),
        })
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.mel_db.nrows()
    }

    /// Whether there are no frames.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Which layout a dataset came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DataLayout {
    /// The synthetic corpus (`manifest.json`).
    Corpus,
    /// URMP (`AuSep_K_vn_NAME.wav` + `openpose_K_vn_NAME/`).
    Urmp,
}

/// Sequences split into training, validation and test sets.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    /// The layout read.
    pub layout: DataLayout,
    /// Training sequences.
    pub train: Vec<Sequence>,
    /// Validation sequences (model selection, learning-rate decay).
    pub val: Vec<Sequence>,
    /// Test sequences (never seen in training).
    pub test: Vec<Sequence>,
}

impl Dataset {
    /// Total frames of the training sequences.
    pub fn train_frames(&self) -> usize {
        self.train.iter().map(Sequence::len).sum()
    }
}
