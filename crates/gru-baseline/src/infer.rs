//! Inference: audio or mel frames → a 30 fps [`Motion`] in pixels.
//!
//! Each layer's input projection for all frames is one matrix product (candle's gemm, both
//! cores); the recurrence runs on plain slices against the recurrent matrix packed once
//! ([`crate::recurrence::forward_parallel`]), its batch rows split over the cores. A single
//! recording becomes a batch by [`Chunking`]; several recordings are a batch already.

use candle_core::{CpuStorage, Device, Storage, Tensor};
use dsp_mel::Audio;
use ndarray::{s, Array2, ArrayView2};
use skeleton::Motion;

use crate::chunking::{sounding_frames, Chunking};
use crate::error::{GruError, Result};
use crate::features::{check_mel, mel_frames, FPS};
use crate::gates::Biases;
use crate::model::GruBaseline;
use crate::packed::PackedMatrix;
use crate::recurrence::forward_parallel;

/// Frames per time segment of the exact (state-carrying) passes: memory is bounded by a
/// segment, not by the recording.
pub const CHUNK_FRAMES: usize = 900;

/// Recordings run side by side in one exact pass.
const EXACT_ROWS_PER_PASS: usize = 16;

/// The network's recurrent weights packed for the inference loops (a few ms to build).
struct Engine<'a> {
    net: &'a GruBaseline,
    w_hh: Vec<PackedMatrix>,
    biases: Vec<Biases>,
}

/// Output of one batch: `(rows, steps, outputs)` row-major and each layer's final state.
struct Batch {
    y: Vec<f32>,
    state: Vec<Vec<f32>>,
}

impl<'a> Engine<'a> {
    fn new(net: &'a GruBaseline) -> Result<Self> {
        let mut w_hh = Vec::new();
        let mut biases = Vec::new();
        for layer in net.layers() {
            let [_, w, b_ih, b_hh] = layer.parameters();
            let w = w.flatten_all()?.to_vec1::<f32>()?;
            w_hh.push(PackedMatrix::from_weight(
                &w,
                3 * layer.hidden(),
                layer.hidden(),
            ));
            let b_ih = b_ih.flatten_all()?.to_vec1::<f32>()?;
            let b_hh = b_hh.flatten_all()?.to_vec1::<f32>()?;
            biases.push(Biases::new(&b_hh, Some(&b_ih)));
        }
        Ok(Self { net, w_hh, biases })
    }

    /// Normalised mel `x` `(rows, steps, bands)` → normalised joints, from `state` (one
    /// `(rows, H)` per layer) or zeros.
    fn run(
        &self,
        x: Vec<f32>,
        rows: usize,
        steps: usize,
        state: Option<&[Vec<f32>]>,
    ) -> Result<Batch> {
        let mut h = x;
        let mut in_dim = self.net.config().n_mels;
        let mut finals = Vec::with_capacity(self.w_hh.len());
        for (l, layer) in self.net.layers().iter().enumerate() {
            let [w_ih, ..] = layer.parameters();
            let hidden = layer.hidden();
            // The input projection of every frame: one gemm; b_ih is added in the gates.
            let xw =
                Tensor::from_vec(h, (rows * steps, in_dim), &Device::Cpu)?.matmul(&w_ih.t()?)?;
            let mut out = vec![0f32; rows * steps * hidden];
            let h0 = state.map(|s| s[l].as_slice());
            with_f32_slice(&xw, |xw| {
                forward_parallel(xw, h0, steps, &self.w_hh[l], &self.biases[l], &mut out)
            })?;
            let mut last = Vec::with_capacity(rows * hidden);
            for r in 0..rows {
                last.extend_from_slice(&out[((r + 1) * steps - 1) * hidden..][..hidden]);
            }
            finals.push(last);
            h = out;
            in_dim = hidden;
        }
        let head = self.net.head();
        let mut y = Tensor::from_vec(h, (rows * steps, in_dim), &Device::Cpu)?
            .matmul(&head.weight().t()?)?;
        if let Some(b) = head.bias() {
            y = y.broadcast_add(b)?;
        }
        Ok(Batch {
            y: y.flatten_all()?.to_vec1::<f32>()?,
            state: finals,
        })
    }
}

/// Runs `f` on the values of a contiguous f32 CPU tensor without copying them.
fn with_f32_slice<R>(t: &Tensor, f: impl FnOnce(&[f32]) -> R) -> Result<R> {
    let (storage, layout) = t.storage_and_layout();
    match (&*storage, layout.contiguous_offsets()) {
        (Storage::Cpu(CpuStorage::F32(v)), Some((a, b))) => Ok(f(&v[a..b])),
        _ => Err(GruError::Config(
            "internal: expected a contiguous f32 CPU tensor".into(),
        )),
    }
}

/// Copies `len` frames of `src` from frame `from` into row `row` of a `(rows, steps, width)`
/// buffer at step `at`.
fn put_rows(
    dst: &mut [f32],
    steps: usize,
    row: usize,
    at: usize,
    src: ArrayView2<f32>,
    from: usize,
    len: usize,
) {
    let width = src.ncols();
    for t in 0..len {
        let d = &mut dst[((row * steps) + at + t) * width..][..width];
        for (d, v) in d.iter_mut().zip(src.row(from + t).iter()) {
            *d = *v;
        }
    }
}

impl GruBaseline {
    /// Standardised mel frames followed by [`crate::Config::lookahead_frames`] zero frames
    /// (the mean spectrum) that flush the last poses out of the delayed output.
    pub(crate) fn network_input(&self, mel_db: ArrayView2<f32>) -> Array2<f32> {
        let x = self.mel_stats().normalize(mel_db);
        let delay = self.config().lookahead_frames;
        if delay == 0 {
            return x;
        }
        let mut padded = Array2::zeros((x.nrows() + delay, x.ncols()));
        padded.slice_mut(s![..x.nrows(), ..]).assign(&x);
        padded
    }

    /// The network's outputs `(frames + delay, 20)` → per-video normalised joints
    /// `(frames, 20)`: drop the delay, undo the coordinate standardisation.
    fn network_output(&self, y: Array2<f32>) -> Array2<f32> {
        let delay = self.config().lookahead_frames;
        let y = if delay == 0 {
            y
        } else {
            y.slice(s![delay.., ..]).to_owned()
        };
        self.target_space().destandardize(y)
    }

    /// Normalised joints `(frames, 20)` for mel frames in dB `(frames, 128)`, chunked as
    /// [`Chunking::default`] says (on corpus-mix's test audio, 0.016 px from the sequential
    /// run on average, 0.3 px at the 99th percentile, 2.7 px at most, see the crate README;
    /// [`GruBaseline::predict_normalized_exact`] is the sequential run).
    ///
    /// Errors: wrong band count → [`GruError::Shape`], no frames → [`GruError::Empty`],
    /// NaN/inf → [`GruError::NonFinite`].
    pub fn predict_normalized(&self, mel_db: ArrayView2<f32>) -> Result<Array2<f32>> {
        self.predict_normalized_with(mel_db, &Chunking::default())
    }

    /// [`GruBaseline::predict_normalized`] with the given chunking.
    pub fn predict_normalized_with(
        &self,
        mel_db: ArrayView2<f32>,
        chunking: &Chunking,
    ) -> Result<Array2<f32>> {
        check_mel(mel_db, self.config().n_mels, "mel input")?;
        let x = self.network_input(mel_db);
        let mut sounding = sounding_frames(mel_db);
        sounding.resize(x.nrows(), false);
        let chunks = chunking.plan(&sounding)?;
        let engine = Engine::new(self)?;
        let (bands, outputs) = (self.config().n_mels, self.config().outputs());
        let mut out = Array2::<f32>::zeros((x.nrows(), outputs));
        for pass in chunks.chunks(chunking.rows_per_pass) {
            let rows = pass.len();
            let steps = pass.iter().map(|c| c.len()).max().unwrap_or(1);
            let mut input = vec![0f32; rows * steps * bands];
            for (r, c) in pass.iter().enumerate() {
                put_rows(&mut input, steps, r, 0, x.view(), c.start, c.len());
            }
            let y = engine.run(input, rows, steps, None)?.y;
            for (r, c) in pass.iter().enumerate() {
                for t in c.keep_from..c.end {
                    let src = &y[(r * steps + t - c.start) * outputs..][..outputs];
                    for (d, v) in out.row_mut(t).iter_mut().zip(src) {
                        *d = *v;
                    }
                }
            }
        }
        Ok(self.network_output(out))
    }

    /// The sequential run: one batch row from frame 0 to the end, the state carried across
    /// segments of [`CHUNK_FRAMES`] (bounded memory, the same result as one pass).
    pub fn predict_normalized_exact(&self, mel_db: ArrayView2<f32>) -> Result<Array2<f32>> {
        let mut out = self.predict_normalized_batch(&[mel_db])?;
        out.pop().ok_or_else(|| GruError::Empty("mel input".into()))
    }

    /// [`GruBaseline::predict_normalized_exact`] of several recordings at once (one batch row
    /// each, zero-padded to the longest of a pass; padding never reaches a real frame because
    /// the GRU runs forward in time). Used for validation and test scores.
    pub fn predict_normalized_batch(
        &self,
        mels_db: &[ArrayView2<f32>],
    ) -> Result<Vec<Array2<f32>>> {
        let bands = self.config().n_mels;
        for (i, m) in mels_db.iter().enumerate() {
            check_mel(*m, bands, &format!("mel input {i}"))?;
        }
        let engine = Engine::new(self)?;
        let outputs = self.config().outputs();
        let mut outs = Vec::with_capacity(mels_db.len());
        let passes = mels_db.len().div_ceil(EXACT_ROWS_PER_PASS).max(1);
        for pass in mels_db.chunks(mels_db.len().div_ceil(passes).max(1)) {
            let normalized: Vec<Array2<f32>> =
                pass.iter().map(|m| self.network_input(*m)).collect();
            let mut pass_out: Vec<Array2<f32>> = normalized
                .iter()
                .map(|x| Array2::zeros((x.nrows(), outputs)))
                .collect();
            let frames = normalized.iter().map(|x| x.nrows()).max().unwrap_or(0);
            let rows = pass.len();
            let mut state: Option<Vec<Vec<f32>>> = None;
            let mut start = 0;
            while start < frames {
                let steps = CHUNK_FRAMES.min(frames - start);
                let mut input = vec![0f32; rows * steps * bands];
                for (r, x) in normalized.iter().enumerate() {
                    let n = x.nrows().saturating_sub(start).min(steps);
                    put_rows(&mut input, steps, r, 0, x.view(), start, n);
                }
                let batch = engine.run(input, rows, steps, state.as_deref())?;
                for (r, out) in pass_out.iter_mut().enumerate() {
                    let n = out.nrows().saturating_sub(start).min(steps);
                    for t in 0..n {
                        let src = &batch.y[(r * steps + t) * outputs..][..outputs];
                        for (d, v) in out.row_mut(start + t).iter_mut().zip(src) {
                            *d = *v;
                        }
                    }
                }
                state = Some(batch.state);
                start += steps;
            }
            outs.extend(pass_out.into_iter().map(|y| self.network_output(y)));
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn put_rows_places_frames_batch_major() {
        let src = ndarray::array![[1.0f32, 2.0], [3.0, 4.0], [5.0, 6.0]];
        let mut dst = vec![0f32; 2 * 3 * 2];
        put_rows(&mut dst, 3, 1, 1, src.view(), 1, 2);
        assert_eq!(dst, vec![0., 0., 0., 0., 0., 0., 0., 0., 3., 4., 5., 6.]);
    }
}
