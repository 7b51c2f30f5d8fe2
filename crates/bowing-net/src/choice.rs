//! [`BowingModel`]: the bow-change CNN of SPEC §4, the stroke network, or both averaged,
//! behind one interface; a weights file is told apart by its format.
//! [`BowingModel::pretrained`] is the shipped default: the ensemble (see the README for the
//! held-out figures that chose it).

use std::path::Path;

use ndarray::ArrayView2;
use net_core::file;

use crate::detector::{BowChangeDetector, FORMAT_NAME};
use crate::error::{NetError, Result};
use crate::features::{bowing_mel, FPS};
use crate::stroke::{FrameOutputs, StrokeAnalysis, StrokeDetector, STROKE_FORMAT_NAME};

/// The shipped stroke-network weights (see the crate README for how they were trained).
static PRETRAINED_STROKES: &[u8] = include_bytes!("../weights/stroke-net.safetensors");

/// The CNN the shipped ensemble averages with the stroke network: the seed design's CNN
/// trained on the many-violin corpus (crate README, step 8). The CNN alone
/// ([`BowChangeDetector::pretrained`]) keeps the weights trained on études.
static PRETRAINED_ENSEMBLE_CNN: &[u8] = include_bytes!("../weights/ensemble-cnn.safetensors");

/// A bowing model: bow changes (both) and strings (stroke network only).
#[derive(Debug)]
pub enum BowingModel {
    /// The seed design's CNN: bow changes only.
    Cnn(BowChangeDetector),
    /// The stroke network: bow changes and strings.
    Strokes(StrokeDetector),
    /// Both: their change probabilities averaged and picked by the stroke network's
    /// ensemble decoder; strings and played stretches from the stroke network.
    Ensemble(Box<BowChangeDetector>, StrokeDetector),
}

impl BowingModel {
    /// The stroke network's direction decoder, when the model has one (never the CNN's).
    pub fn direction_decoder(&self) -> Option<crate::stroke::direction::DirectionDecoder> {
        match self {
            Self::Cnn(_) => None,
            Self::Strokes(d) | Self::Ensemble(_, d) => d.direction_decoder(),
        }
    }

    /// The shipped default: the ensemble of the CNN and the stroke network (the stroke
    /// network alone if its weights carry no ensemble decoder).
    pub fn pretrained() -> Result<Self> {
        let strokes = Self::pretrained_strokes()?;
        if strokes.ensemble_decoder().is_some() {
            Ok(Self::Ensemble(
                Box::new(Self::pretrained_ensemble_cnn()?),
                strokes,
            ))
        } else {
            Ok(Self::Strokes(strokes))
        }
    }

    /// The shipped stroke network alone.
    pub fn pretrained_strokes_only() -> Result<Self> {
        Ok(Self::Strokes(Self::pretrained_strokes()?))
    }

    /// The shipped stroke network.
    pub fn pretrained_strokes() -> Result<StrokeDetector> {
        StrokeDetector::from_bytes(
            PRETRAINED_STROKES,
            Path::new("<embedded bowing stroke-net weights>"),
        )
    }

    /// The CNN of the shipped ensemble: the seed design's network (SPEC §4) trained on the
    /// many-violin corpus, not the études [`BowChangeDetector::pretrained`] learnt from.
    pub fn pretrained_ensemble_cnn() -> Result<BowChangeDetector> {
        BowChangeDetector::from_bytes(
            PRETRAINED_ENSEMBLE_CNN,
            Path::new("<embedded ensemble CNN weights>"),
        )
    }

    /// The shipped CNN (SPEC §4), trained on études.
    pub fn pretrained_cnn() -> Result<Self> {
        Ok(Self::Cnn(BowChangeDetector::pretrained()?))
    }

    /// The shipped ensemble's CNN averaged with the stroke network of `path` (a
    /// `train_strokes` file that carries an ensemble decoder), as [`BowingModel::pretrained`]
    /// averages it with the shipped stroke network: how a retrained stroke network runs as
    /// the default model does.
    pub fn ensemble_with_strokes_file(path: &Path) -> Result<Self> {
        Self::ensemble_from_files(None, Some(path))
    }

    /// The ensemble with either half from a file: `cnn` a `violin-skeleton train bowing`
    /// file in place of [`BowingModel::pretrained_ensemble_cnn`], `strokes` a
    /// `train_strokes` file (which must carry an ensemble decoder) in place of the shipped
    /// stroke network; `None` keeps the shipped half. A file of the other network is refused
    /// with its path.
    pub fn ensemble_from_files(cnn: Option<&Path>, strokes: Option<&Path>) -> Result<Self> {
        let strokes = match strokes {
            Some(path) => {
                let d = Self::strokes_file(path)?;
                if d.ensemble_decoder().is_none() {
                    return Err(NetError::weights(
                        path,
                        "carries no ensemble decoder, so it cannot be averaged with the CNN \
                         (write one with `train_strokes … --eval FILE --write-ensemble`, or \
                         run the stroke network alone)",
                    ));
                }
                d
            }
            None => Self::pretrained_strokes()?,
        };
        let cnn = match cnn {
            Some(path) => Self::cnn_file(path)?,
            None => Self::pretrained_ensemble_cnn()?,
        };
        Ok(Self::Ensemble(Box::new(cnn), strokes))
    }

    /// The bow-change CNN of `path`; a file of the stroke network is refused.
    pub fn cnn_file(path: &Path) -> Result<BowChangeDetector> {
        match Self::load(path)? {
            Self::Cnn(d) => Ok(d),
            _ => Err(NetError::weights(
                path,
                "holds a stroke network, not the bow-change CNN (SPEC §4)",
            )),
        }
    }

    /// The stroke network of `path`; a file of the CNN is refused.
    pub fn strokes_file(path: &Path) -> Result<StrokeDetector> {
        match Self::load(path)? {
            Self::Strokes(d) => Ok(d),
            _ => Err(NetError::weights(
                path,
                "holds the bow-change CNN (SPEC §4), not a stroke network",
            )),
        }
    }

    /// Reads a weights file of either network, told apart by its `format` metadata.
    pub fn load(path: &Path) -> Result<Self> {
        let bytes = std::fs::read(path)
            .map_err(|e| NetError::weights(path, format!("cannot read the weights file ({e})")))?;
        let parsed = file::decode(&bytes, path)?;
        let format = parsed
            .metadata
            .get(net_core::KEY_FORMAT)
            .map(String::as_str)
            .unwrap_or("");
        match format {
            STROKE_FORMAT_NAME => Ok(Self::Strokes(StrokeDetector::from_bytes(&bytes, path)?)),
            FORMAT_NAME => Ok(Self::Cnn(BowChangeDetector::from_bytes(&bytes, path)?)),
            other => Err(NetError::weights(
                path,
                format!(
                    "format \"{other}\" is neither {STROKE_FORMAT_NAME} nor {FORMAT_NAME}; \
                     give weights written by `violin-skeleton train bowing`"
                ),
            )),
        }
    }

    /// Bow changes (and, for the stroke network, played stretches and strings) of a
    /// recording.
    pub fn analyze_audio(&self, audio: &dsp_mel::Audio) -> Result<StrokeAnalysis> {
        self.analyze_mel(bowing_mel(audio)?.view())
    }

    /// [`BowingModel::analyze_audio`] of a 30 fps × 128 mel dB spectrogram
    /// ([`crate::features::bowing_mel`]).
    pub fn analyze_mel(&self, mel: ArrayView2<f32>) -> Result<StrokeAnalysis> {
        match self {
            Self::Strokes(d) => d.analyze_mel(mel),
            Self::Ensemble(cnn, strokes) => {
                let probs = cnn.frame_probabilities(mel)?;
                strokes.analyze_mel_with(mel, Some(&probs))
            }
            Self::Cnn(d) => {
                let probs = d.frame_probabilities(mel)?;
                Ok(StrokeAnalysis {
                    bow_changes_s: d
                        .decoder()
                        .pick_fractional(&probs)
                        .into_iter()
                        .map(|f| f / FPS)
                        .collect(),
                    played_s: Vec::new(),
                    frames: FrameOutputs {
                        change: probs,
                        ..FrameOutputs::default()
                    },
                    direction_decoder: None,
                })
            }
        }
    }
}
