//! The network's shape (SPEC §8).

use serde::{Deserialize, Serialize};

use crate::error::{GruError, Result};

/// Longest output delay accepted, frames (10 s).
pub const MAX_LOOKAHEAD_FRAMES: usize = 300;

/// Output delay of [`Config::default`], frames (see [`Config::lookahead_frames`]).
pub const DEFAULT_LOOKAHEAD_FRAMES: usize = 30;

/// Sizes of the Method 1 network: mel bands in, stacked GRU widths, dropout, joints out.
///
/// The default is SPEC §8: 128 bands → GRU 256 → dropout .3 → GRU 512 → dropout .3 →
/// GRU 256 → dropout .3 → dense 20 (10 joints × x, y).
///
/// ```
/// let cfg = gru_baseline::Config::default();
/// assert_eq!((cfg.n_mels, cfg.hidden.as_slice(), cfg.dropout, cfg.outputs()), (128, &[256, 512, 256][..], 0.3, 20));
/// assert_eq!(cfg.parameter_count(), 2_075_668);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Config {
    /// Mel bands per input frame (128).
    pub n_mels: usize,
    /// Hidden size of each stacked GRU layer, input side first.
    pub hidden: Vec<usize>,
    /// Dropout probability after every GRU layer (training only).
    pub dropout: f32,
    /// Joints predicted (x and y each), in `skeleton::Joint::ALL` order.
    pub joints: usize,
    /// Output delay, frames: the output at input frame `t` is the pose of frame
    /// `t − lookahead_frames`, so each pose is predicted having heard that much of what follows
    /// (inputs are padded at the end to flush the last poses). The layers are unchanged; 0 is
    /// the strictly causal network.
    #[serde(default)]
    pub lookahead_frames: usize,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            n_mels: 128,
            hidden: vec![256, 512, 256],
            dropout: 0.3,
            joints: skeleton::JOINT_COUNT,
            lookahead_frames: DEFAULT_LOOKAHEAD_FRAMES,
        }
    }
}

impl Config {
    /// Output values per frame (`2 × joints`).
    pub fn outputs(&self) -> usize {
        2 * self.joints
    }

    /// Checks every size, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        if self.n_mels == 0 || self.n_mels > 4096 {
            return Err(GruError::Config(format!(
                "n_mels {} must be in 1..=4096",
                self.n_mels
            )));
        }
        if self.hidden.is_empty() || self.hidden.iter().any(|&h| h == 0 || h > 8192) {
            return Err(GruError::Config(format!(
                "hidden sizes {:?} must be one or more values in 1..=8192",
                self.hidden
            )));
        }
        if !(0.0..1.0).contains(&self.dropout) {
            return Err(GruError::Config(format!(
                "dropout {} must be in [0, 1)",
                self.dropout
            )));
        }
        if self.lookahead_frames > MAX_LOOKAHEAD_FRAMES {
            return Err(GruError::Config(format!(
                "lookahead {} frames must be at most {MAX_LOOKAHEAD_FRAMES}",
                self.lookahead_frames
            )));
        }
        if self.joints != skeleton::JOINT_COUNT {
            return Err(GruError::Config(format!(
                "joints {} must be {} (the skeleton's joint set)",
                self.joints,
                skeleton::JOINT_COUNT
            )));
        }
        Ok(())
    }

    /// Number of trainable parameters.
    pub fn parameter_count(&self) -> usize {
        let mut count = 0;
        let mut input = self.n_mels;
        for &h in &self.hidden {
            count += 3 * h * (input + h) + 6 * h;
            input = h;
        }
        count + input * self.outputs() + self.outputs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validate_names_the_bad_size() {
        assert!(Config::default().validate().is_ok());
        let cases = [
            Config {
                n_mels: 0,
                ..Config::default()
            },
            Config {
                hidden: vec![],
                ..Config::default()
            },
            Config {
                dropout: 1.0,
                ..Config::default()
            },
            Config {
                joints: 9,
                ..Config::default()
            },
            Config {
                lookahead_frames: MAX_LOOKAHEAD_FRAMES + 1,
                ..Config::default()
            },
        ];
        for (cfg, word) in cases
            .iter()
            .zip(["n_mels", "hidden", "dropout", "joints", "lookahead"])
        {
            let e = cfg.validate().unwrap_err().to_string();
            assert!(e.contains(word), "{e}");
        }
    }
}
