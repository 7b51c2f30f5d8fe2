//! The network-weight flags shared by the commands that analyse audio (`analyze`,
//! `generate`, `evaluate`): which embedded model, or which trained file, each network uses.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use violin_skeleton::PipelineBuilder;

use crate::contract::{named, NamedPath};

/// The `--bowing-weights` / `--emotion-weights` / `--beat-weights` flags of every command
/// that analyses audio (`None`: the embedded defaults).
#[derive(Debug, Clone, Default, Args)]
pub struct AnalysisWeights {
    /// Bowing weights from `train bowing` or the `train_strokes` example: the stroke
    /// network or the CNN, told apart by the file. The file's network runs alone with its
    /// own decoder (not averaged with the other; `--bowing-net` is then not used; to run a
    /// retrained stroke network inside the ensemble, use `--stroke-weights`). Default:
    /// the embedded model `--bowing-net` chooses.
    #[arg(long, conflicts_with = "stroke_weights")]
    pub bowing_weights: Option<PathBuf>,
    /// Stroke-network weights from the `train_strokes` example in place of the embedded
    /// stroke network, inside the model `--bowing-net` chooses: `ensemble` (default)
    /// averages it with the embedded CNN by the file's ensemble decoder, as the shipped
    /// model does; `strokes` runs it alone.
    #[arg(long)]
    pub stroke_weights: Option<PathBuf>,
    /// Bow-change CNN weights from `train bowing` in place of the embedded ensemble's CNN,
    /// averaged with the stroke network (the embedded one or `--stroke-weights`) as the
    /// shipped model does. Only with `--bowing-net ensemble`; to run a CNN file alone, give
    /// it as `--bowing-weights`.
    #[arg(long, conflicts_with = "bowing_weights")]
    pub ensemble_cnn_weights: Option<PathBuf>,
    /// The embedded bowing model: `ensemble` (the two below averaged), `strokes` (bow
    /// changes and strings, trained on the many-violin corpus) or `cnn` (the seed design's
    /// bow-change CNN).
    #[arg(long, value_enum, default_value_t = BowingNetArg::Ensemble)]
    pub bowing_net: BowingNetArg,
    /// Arousal CRNN weights from `train emotion` (default: embedded).
    #[arg(long)]
    pub emotion_weights: Option<PathBuf>,
    /// Beat tracker: `learned` (beat-net activation + bar-pointer decoding) or `classic`
    /// (onset tempogram + dynamic programming; no learned weights).
    #[arg(long, value_enum, default_value_t = BeatArg::Learned)]
    pub beats: BeatArg,
    /// Beat/downbeat network weights from the `train_beats` example, for `--beats learned`
    /// (default: embedded).
    #[arg(long)]
    pub beat_weights: Option<PathBuf>,
}

/// The `--beats` choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum BeatArg {
    /// beat-net + bar-pointer decoding.
    #[default]
    Learned,
    /// The classic onset/DP tracker.
    Classic,
}

/// `--bowing-net`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum BowingNetArg {
    /// The CNN and the stroke network averaged (default).
    #[default]
    Ensemble,
    /// The stroke network.
    Strokes,
    /// The seed design's CNN (SPEC §4).
    Cnn,
}

/// The weight flags of the commands that make motion: the analysis networks and Method 1.
#[derive(Debug, Clone, Default, Args)]
pub struct NetworkWeights {
    /// The analysis networks.
    #[command(flatten)]
    pub analysis: AnalysisWeights,
    /// Method 1 GRU weights from `train gru` (default: embedded; used with `--method gru`).
    #[arg(long)]
    pub gru_weights: Option<PathBuf>,
}

impl AnalysisWeights {
    /// The weight files given, as inputs of the output contract.
    pub fn inputs(&self) -> Vec<NamedPath<'_>> {
        let mut v = Vec::new();
        if let Some(p) = &self.bowing_weights {
            v.push(named("--bowing-weights", p));
        }
        if let Some(p) = &self.stroke_weights {
            v.push(named("--stroke-weights", p));
        }
        if let Some(p) = &self.ensemble_cnn_weights {
            v.push(named("--ensemble-cnn-weights", p));
        }
        if let Some(p) = &self.emotion_weights {
            v.push(named("--emotion-weights", p));
        }
        if let Some(p) = &self.beat_weights {
            v.push(named("--beat-weights", p));
        }
        v
    }

    /// Sets the given weight files on a pipeline builder.
    pub fn apply(&self, mut builder: PipelineBuilder) -> PipelineBuilder {
        builder = builder.bowing_network(match self.bowing_net {
            BowingNetArg::Ensemble => violin_skeleton::BowingNetwork::Ensemble,
            BowingNetArg::Strokes => violin_skeleton::BowingNetwork::Strokes,
            BowingNetArg::Cnn => violin_skeleton::BowingNetwork::Cnn,
        });
        if let Some(p) = &self.bowing_weights {
            builder = builder.bowing_weights(p);
        }
        if let Some(p) = &self.stroke_weights {
            builder = builder.stroke_weights(p);
        }
        if let Some(p) = &self.ensemble_cnn_weights {
            builder = builder.ensemble_cnn_weights(p);
        }
        if let Some(p) = &self.emotion_weights {
            builder = builder.emotion_weights(p);
        }
        if let Some(p) = &self.beat_weights {
            builder = builder.beat_weights(p);
        }
        builder.beat_method(match self.beats {
            BeatArg::Learned => violin_skeleton::BeatMethod::Learned,
            BeatArg::Classic => violin_skeleton::BeatMethod::Classic,
        })
    }
}
