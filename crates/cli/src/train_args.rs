//! The arguments of `violin-skeleton train`.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

/// Which network to train.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Network {
    /// The bow-change CNN (corpus or URMP layout).
    Bowing,
    /// The arousal CRNN (corpus or DEAM layout).
    Emotion,
    /// Method 1: the GRU from mel frames straight to the joints (corpus or URMP layout).
    Gru,
}

/// Arguments of `train`.
#[derive(Debug, Args)]
#[command(
    after_help = "Examples:\n  violin-skeleton train bowing --data corpus --out bowing.safetensors\n  violin-skeleton train emotion --data DEAM --out emotion.safetensors --epochs 40 --seed 2\n  violin-skeleton train gru --data corpus --out gru.safetensors --unweighted --epochs 20\n  violin-skeleton train bowing --data corpus --out bowing.safetensors --resume\n  violin-skeleton train bowing --data corpus --out b.safetensors --config settings.json\n  violin-skeleton train bowing --data corpus --extra-train corpus2 --out b.safetensors --config steps.json\n\nThe data folder's layout is recognised: a corpus (manifest.json, from `violin-skeleton corpus`),\nURMP (AuSep_K_vn_NAME.wav + openpose_K_vn_NAME/ per track; bowing and gru) or DEAM\n(annotations/… + MEMD_audio/; emotion only). The best weights so far are kept in --out and a\ncheckpoint beside it (NAME.ckpt.safetensors) after every epoch; --resume continues from it.\nWith --extra-train, {\"max_steps_per_epoch\": N} in --config keeps an epoch at N steps.\nAt the end the test split is evaluated and summarised."
)]
pub struct TrainArgs {
    /// The network.
    #[arg(value_enum)]
    pub network: Network,
    /// Training data folder.
    #[arg(long)]
    pub data: PathBuf,
    /// Output weights (safetensors).
    #[arg(long)]
    pub out: PathBuf,
    /// Maximum epochs (early stopping may end sooner).
    #[arg(long)]
    pub epochs: Option<usize>,
    /// Continue from the checkpoint beside --out.
    #[arg(long)]
    pub resume: bool,
    /// Seed of initialisation, order and dropout.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// bowing, emotion: training settings as JSON, any fields of the network's `TrainConfig`
    /// (e.g. {"learning_rate": 0.002, "patience": 6}); --epochs and --seed override it.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// bowing: also train on the training split of this corpus (repeatable): a corpus of other
    /// works (another `--seed`) or one played by another training violin (`corpus …
    /// --training-violin V`). Validation and test stay those of --data. Check that none of its
    /// training works is a validation or test work of --data.
    #[arg(long = "extra-train", value_name = "CORPUS")]
    pub extra_train: Vec<PathBuf>,
    /// Also write the test-split evaluation as JSON here.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// gru: the right-arm weighted loss (3× on the right shoulder, elbow, wrist; the default).
    #[arg(long, conflicts_with = "unweighted")]
    pub weighted: bool,
    /// gru: plain MSE on all joints.
    #[arg(long)]
    pub unweighted: bool,
}
