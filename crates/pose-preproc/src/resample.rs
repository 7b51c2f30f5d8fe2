//! Resampling a skeleton to another frame rate (e.g. a 60 fps clip's skeleton to the
//! product's 30 fps).

use ndarray::Array3;
use skeleton::Motion;

use crate::error::{PosePreprocError, Result};

/// `motion` at `fps` by linear interpolation between the two nearest frames; frame `k` of the
/// result is at time `k / fps`, and the result covers the source's duration (at least one
/// frame). Only the 2-D joints are kept.
///
/// ```
/// use ndarray::Array3;
/// let mut frames = Array3::<f32>::zeros((60, 10, 2));
/// for t in 0..60 { frames[[t, 4, 0]] = t as f32; }
/// let m = skeleton::Motion::new(60.0, frames)?;
/// let r = pose_preproc::resample::resample(&m, 30.0)?;
/// assert_eq!((r.len(), r.fps()), (30, 30.0));
/// assert_eq!(r.frames()[[10, 4, 0]], 20.0);
/// # Ok::<(), pose_preproc::PosePreprocError>(())
/// ```
pub fn resample(motion: &Motion, fps: f64) -> Result<Motion> {
    if !(fps.is_finite() && fps > 0.0) {
        return Err(PosePreprocError::InvalidConfig(format!(
            "resampling fps must be positive, got {fps}"
        )));
    }
    let src = motion.frames();
    let n = motion.len();
    let (_, joints, dims) = src.dim();
    if n == 0 || (fps - motion.fps()).abs() < 1e-9 {
        return Ok(Motion::new(fps, src.clone())?);
    }
    let ratio = motion.fps() / fps;
    let out_len = ((n as f64 / ratio).floor() as usize).max(1);
    let mut out = Array3::<f32>::zeros((out_len, joints, dims));
    for k in 0..out_len {
        let pos = (k as f64 * ratio).min((n - 1) as f64);
        let i = pos.floor() as usize;
        let j = (i + 1).min(n - 1);
        let w = (pos - i as f64) as f32;
        for a in 0..joints {
            for c in 0..dims {
                out[[k, a, c]] = src[[i, a, c]] * (1.0 - w) + src[[j, a, c]] * w;
            }
        }
    }
    Ok(Motion::new(fps, out)?)
}
