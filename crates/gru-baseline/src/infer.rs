//! Inference: audio or mel frames → a 30 fps [`Motion`] in pixels, in chunks that carry the
//! GRU state (memory bounded by the chunk, not the recording).

use candle_core::{Device, Tensor};
use dsp_mel::Audio;
use ndarray::{s, Array2, ArrayView2};
use skeleton::Motion;

use crate::error::Result;
use crate::features::{check_mel, mel_frames, FPS};
use crate::model::{GruBaseline, GruState};

/// Frames per inference chunk (30 s); the GRU state is carried from chunk to chunk, so the
/// output does not depend on it.
pub const CHUNK_FRAMES: usize = 900;

impl GruBaseline {
    /// Normalised joints `(frames, 20)` for mel frames in dB `(frames, 128)`.
    ///
    /// Errors: wrong band count → [`crate::GruError::Shape`], no frames →
    /// [`crate::GruError::Empty`], NaN/inf → [`crate::GruError::NonFinite`].
    pub fn predict_normalized(&self, mel_db: ArrayView2<f32>) -> Result<Array2<f32>> {
        check_mel(mel_db, self.config().n_mels, "mel input")?;
        let x = self.mel_stats().normalize(mel_db);
        let frames = x.nrows();
        let bands = x.ncols();
        let outputs = self.config().outputs();
        let mut out = Array2::<f32>::zeros((frames, outputs));
        let mut state: Option<GruState> = None;
        let mut start = 0;
        while start < frames {
            let end = (start + CHUNK_FRAMES).min(frames);
            let chunk = x.slice(s![start..end, ..]);
            let data: Vec<f32> = chunk.iter().copied().collect();
            let xs = Tensor::from_vec(data, (1, end - start, bands), &Device::Cpu)?;
            let (y, next) = self.forward_state(&xs, state.as_ref(), false)?;
            let y = y.squeeze(0)?.flatten_all()?.to_vec1::<f32>()?;
            let y = Array2::from_shape_vec((end - start, outputs), y)
                .map_err(|e| crate::GruError::Config(format!("output reshape: {e}")))?;
            out.slice_mut(s![start..end, ..]).assign(&y);
            state = Some(next);
            start = end;
        }
        Ok(out)
    }

    /// [`GruBaseline::predict_normalized`] of several recordings at once (one batch row each,
    /// zero-padded to the longest; padding never reaches a real frame because the GRU runs
    /// forward in time). Faster than one by one on a CPU.
    pub fn predict_normalized_batch(
        &self,
        mels_db: &[ArrayView2<f32>],
    ) -> Result<Vec<Array2<f32>>> {
        let bands = self.config().n_mels;
        for (i, m) in mels_db.iter().enumerate() {
            check_mel(*m, bands, &format!("mel input {i}"))?;
        }
        let batch = mels_db.len();
        let frames = mels_db.iter().map(|m| m.nrows()).max().unwrap_or(0);
        if batch == 0 {
            return Ok(Vec::new());
        }
        let normalized: Vec<Array2<f32>> = mels_db
            .iter()
            .map(|m| self.mel_stats().normalize(*m))
            .collect();
        let outputs = self.config().outputs();
        let mut outs: Vec<Array2<f32>> = mels_db
            .iter()
            .map(|m| Array2::zeros((m.nrows(), outputs)))
            .collect();
        let mut state: Option<GruState> = None;
        let mut start = 0;
        while start < frames {
            let end = (start + CHUNK_FRAMES).min(frames);
            let n = end - start;
            let mut data = vec![0f32; batch * n * bands];
            for (b, x) in normalized.iter().enumerate() {
                for t in start..end.min(x.nrows()) {
                    let row = x.row(t);
                    let dst = &mut data[(b * n + t - start) * bands..][..bands];
                    for (d, v) in dst.iter_mut().zip(row.iter()) {
                        *d = *v;
                    }
                }
            }
            let xs = Tensor::from_vec(data, (batch, n, bands), &Device::Cpu)?;
            let (y, next) = self.forward_state(&xs, state.as_ref(), false)?;
            let y = y.flatten_all()?.to_vec1::<f32>()?;
            for (b, out) in outs.iter_mut().enumerate() {
                for t in start..end.min(out.nrows()) {
                    let src = &y[(b * n + t - start) * outputs..][..outputs];
                    for (d, v) in out.row_mut(t).iter_mut().zip(src) {
                        *d = *v;
                    }
                }
            }
            state = Some(next);
            start = end;
        }
        Ok(outs)
    }

    /// A 30 fps [`Motion`] in the training targets' image space (the corpus camera's
    /// 1280×720 frame for the shipped weights), one frame per mel frame.
    pub fn predict_mel(&self, mel_db: ArrayView2<f32>) -> Result<Motion> {
        let normalized = self.predict_normalized(mel_db)?;
        self.target_space().to_motion(normalized.view(), FPS)
    }

    /// Audio (any rate) → 30 fps [`Motion`]: mel frames ([`mel_frames`]), then
    /// [`GruBaseline::predict_mel`].
    ///
    /// ```
    /// let net = gru_baseline::GruBaseline::pretrained()?;
    /// let tone: Vec<f32> = (0..44_100).map(|i| 0.3 * (i as f32 * 0.06).sin()).collect();
    /// let motion = net.generate(&dsp_mel::Audio::new(tone, 44_100)?)?;
    /// assert_eq!((motion.len(), motion.fps()), (31, 30.0));
    /// # Ok::<(), gru_baseline::GruError>(())
    /// ```
    pub fn generate(&self, audio: &Audio) -> Result<Motion> {
        self.predict_mel(mel_frames(audio)?.view())
    }
}
