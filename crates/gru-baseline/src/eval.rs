//! Scores of the network on held-out sequences, and the L1 joint distance.

use ndarray::{ArrayView2, Axis};
use serde::Serialize;
use skeleton::Motion;

use crate::data::Sequence;
use crate::error::{GruError, Result};
use crate::loss::Loss;
use crate::model::GruBaseline;

/// Scores over a set of sequences (frame-weighted).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Scores {
    /// The training loss (its own weights), in the network's standardised units.
    pub loss: f64,
    /// Plain MSE on per-video normalised joints (torso lengths²).
    pub mse: f64,
    /// Mean |error| per coordinate in pixels, each video de-normalised with its own centre
    /// and torso length.
    pub l1_px: f64,
    /// Frames scored.
    pub frames: usize,
}

/// Mean absolute difference per coordinate (x and y of every joint, every frame) between
/// two motions, in their units (pixels); compared over the shorter length.
///
/// ```
/// use ndarray::Array3;
/// let a = skeleton::Motion::new(30.0, Array3::zeros((4, 10, 2)))?;
/// let b = skeleton::Motion::new(30.0, Array3::from_elem((3, 10, 2), 2.0))?;
/// assert_eq!(gru_baseline::eval::l1_px(&a, &b, None)?, 2.0);
/// # Ok::<(), gru_baseline::GruError>(())
/// ```
pub fn l1_px(pred: &Motion, truth: &Motion, joint: Option<skeleton::Joint>) -> Result<f64> {
    let n = pred.len().min(truth.len());
    if n == 0 {
        return Err(GruError::Empty("motion to compare".into()));
    }
    let (p, t) = (pred.frames(), truth.frames());
    let joints: Vec<usize> = match joint {
        Some(j) => vec![j.index()],
        None => (0..skeleton::JOINT_COUNT).collect(),
    };
    let mut sum = 0f64;
    for f in 0..n {
        for &j in &joints {
            for d in 0..2 {
                sum += f64::from((p[[f, j, d]] - t[[f, j, d]]).abs());
            }
        }
    }
    Ok(sum / (n * joints.len() * 2) as f64)
}

/// Runs `net` over `seqs` (batched) and scores it against their joints.
pub fn evaluate(net: &GruBaseline, seqs: &[Sequence], loss: &Loss) -> Result<Scores> {
    if seqs.is_empty() {
        return Err(GruError::Empty("evaluation sequences".into()));
    }
    let mels: Vec<ArrayView2<f32>> = seqs.iter().map(|s| s.mel_db.view()).collect();
    let preds = net.predict_normalized_batch(&mels)?;
    let mse = Loss::mse();
    let (mut l, mut m, mut l1, mut frames) = (0f64, 0f64, 0f64, 0usize);
    for (seq, pred) in seqs.iter().zip(&preds) {
        let n = seq.len();
        let space = net.target_space();
        let (z_pred, z_true) = (
            space.standardize(pred.view()),
            space.standardize(seq.joints.view()),
        );
        l += loss.compute_array(z_pred.view(), z_true.view())? * n as f64;
        m += mse.compute_array(pred.view(), seq.joints.view())? * n as f64;
        let abs: f64 = (pred - &seq.joints)
            .mapv(|v| f64::from(v.abs()))
            .sum_axis(Axis(1))
            .sum();
        l1 += abs / pred.ncols() as f64 * f64::from(seq.video.torso_px);
        frames += n;
    }
    let f = frames as f64;
    Ok(Scores {
        loss: l / f,
        mse: m / f,
        l1_px: l1 / f,
        frames,
    })
}
