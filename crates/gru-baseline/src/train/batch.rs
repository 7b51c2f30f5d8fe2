//! The training examples: every sequence's network input (standardised mel, padded by the
//! output delay) and target (standardised joints, delayed), and the batch of one update.

use candle_core::{Device, Tensor};
use ndarray::Array2;

use super::schedule::Window;
use crate::data::Sequence;
use crate::error::Result;
use crate::model::GruBaseline;

/// Inputs and targets of the training sequences, in the network's units.
pub(crate) struct Examples {
    /// `(frames + delay, bands)` per sequence.
    inputs: Vec<Array2<f32>>,
    /// `(frames, outputs)` per sequence; input frame `t` predicts target frame `t − delay`.
    targets: Vec<Array2<f32>>,
    delay: usize,
}

impl Examples {
    /// Prepares `seqs` with `net`'s normalisation and output delay.
    pub fn new(net: &GruBaseline, seqs: &[Sequence]) -> Self {
        Self {
            inputs: seqs
                .iter()
                .map(|s| net.network_input(s.mel_db.view()))
                .collect(),
            targets: seqs
                .iter()
                .map(|s| net.target_space().standardize(s.joints.view()))
                .collect(),
            delay: net.config().lookahead_frames,
        }
    }

    /// Input frames of every sequence (what the windows cut).
    pub fn lengths(&self) -> Vec<usize> {
        self.inputs.iter().map(|a| a.nrows()).collect()
    }

    /// The batch of one step: inputs `(B, T, bands)`, targets `(B, T, outputs)`, mask
    /// `(B, T)`, `T` the longest window of the step; shorter windows, finished streams and the
    /// first `delay` frames of a sequence (no pose to predict yet) are masked out.
    pub fn batch(&self, row: &[Option<Window>]) -> Result<(Tensor, Tensor, Tensor)> {
        let batch = row.len();
        let steps = row.iter().flatten().map(|w| w.len).max().unwrap_or(1);
        let bands = self.inputs.first().map_or(0, |a| a.ncols());
        let outputs = self.targets.first().map_or(0, |a| a.ncols());
        let mut x = vec![0f32; batch * steps * bands];
        let mut y = vec![0f32; batch * steps * outputs];
        let mut m = vec![0f32; batch * steps];
        for (b, w) in row.iter().enumerate() {
            let Some(w) = w else { continue };
            let (mel, joints) = (&self.inputs[w.seq], &self.targets[w.seq]);
            for t in 0..w.len {
                let frame = w.start + t;
                let dst = &mut x[(b * steps + t) * bands..][..bands];
                dst.iter_mut()
                    .zip(mel.row(frame).iter())
                    .for_each(|(d, s)| *d = *s);
                let Some(target) = frame.checked_sub(self.delay) else {
                    continue;
                };
                let dst = &mut y[(b * steps + t) * outputs..][..outputs];
                dst.iter_mut()
                    .zip(joints.row(target).iter())
                    .for_each(|(d, s)| *d = *s);
                m[b * steps + t] = 1.0;
            }
        }
        Ok((
            Tensor::from_vec(x, (batch, steps, bands), &Device::Cpu)?,
            Tensor::from_vec(y, (batch, steps, outputs), &Device::Cpu)?,
            Tensor::from_vec(m, (batch, steps), &Device::Cpu)?,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;
    use crate::norm::VideoNorm;
    use candle_core::DType;

    #[test]
    fn delayed_targets_line_up_and_the_delay_is_masked() {
        let cfg = Config {
            hidden: vec![4, 4, 4],
            lookahead_frames: 2,
            ..Config::default()
        };
        let vars = GruBaseline::init_vars(&cfg, 1).unwrap();
        let net = GruBaseline::new(
            &cfg,
            candle_nn::VarBuilder::from_varmap(&vars, DType::F32, &Device::Cpu),
        )
        .unwrap();
        let seq = Sequence {
            name: "s".into(),
            mel_db: Array2::from_shape_fn((5, 128), |(t, _)| t as f32),
            joints: Array2::from_shape_fn((5, 20), |(t, _)| 10.0 + t as f32),
            video: VideoNorm {
                center_px: [0.0, 0.0],
                torso_px: 1.0,
            },
            image_size: None,
        };
        let ex = Examples::new(&net, &[seq]);
        assert_eq!(ex.lengths(), vec![7]);
        let w = Window {
            seq: 0,
            start: 1,
            len: 6,
            first: false,
        };
        let (x, y, m) = ex.batch(&[Some(w), None]).unwrap();
        assert_eq!(x.dims(), &[2, 6, 128]);
        let x = x.to_vec3::<f32>().unwrap();
        let y = y.to_vec3::<f32>().unwrap();
        let m = m.to_vec2::<f32>().unwrap();
        // Input frames 1..5 are the mel, 5 and 6 the zero padding.
        assert_eq!(x[0][0][0], 1.0);
        assert_eq!((x[0][4][0], x[0][5][0]), (0.0, 0.0));
        // Input frame 1 has no target yet; frame 2 predicts pose 0, frame 6 pose 4.
        assert_eq!(m[0], vec![0.0, 1.0, 1.0, 1.0, 1.0, 1.0]);
        assert_eq!((y[0][1][0], y[0][5][0]), (10.0, 14.0));
        assert_eq!(m[1], vec![0.0; 6]);
    }
}
