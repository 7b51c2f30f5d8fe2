//! How a long recording is cut into chunks that run side by side as one batch.
//!
//! The recurrence is sequential in time, so one recording is one matrix–*vector* product
//! per frame and layer: memory-bound, and on one core. Cutting the recording into `B`
//! chunks that run as the rows of one batch turns it into matrix–*matrix* products (each
//! weight read once for `B` rows) and lets the rows be split over the cores. A chunk cannot
//! know the state the previous chunk ends in, so it starts early from a zero state and
//! throws the outputs of that warm-up away: a GRU's memory of the far past fades while its
//! input drives it, so after the warm-up the state has converged to the one the unbroken run
//! would have. Not through silence, though: in a rest nothing overwrites the memory (the
//! network holds the last bow position, as the player does), so a warm-up counts only
//! *sounding* frames and reaches back over rests, up to [`MAX_WARMUP_FACTOR`] times its
//! length. How close the result is to the sequential run is measured on corpus audio
//! (crate README; test `chunked_inference_matches_the_sequential_run`).

use ndarray::ArrayView2;

use crate::error::{GruError, Result};

/// A frame is silent when its loudest mel band is this far below the recording's loudest.
pub const SILENCE_BELOW_PEAK_DB: f32 = 40.0;

/// A warm-up reaches back at most this many times `warmup_frames` to find its sounding
/// frames.
pub const MAX_WARMUP_FACTOR: usize = 3;

/// Which frames of a mel spectrogram in dB `(frames, bands)` are sounding (their loudest band
/// within [`SILENCE_BELOW_PEAK_DB`] of the recording's loudest).
///
/// ```
/// let mel = ndarray::array![[-80.0f32, -70.0], [-10.0, 0.0], [-45.0, -60.0]];
/// assert_eq!(gru_baseline::chunking::sounding_frames(mel.view()), vec![false, true, false]);
/// ```
pub fn sounding_frames(mel_db: ArrayView2<f32>) -> Vec<bool> {
    let loudest: Vec<f32> = mel_db
        .rows()
        .into_iter()
        .map(|r| r.iter().copied().fold(f32::NEG_INFINITY, f32::max))
        .collect();
    let peak = loudest.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    loudest
        .iter()
        .map(|&l| l > peak - SILENCE_BELOW_PEAK_DB)
        .collect()
}

/// Warm-up of [`Chunking::default`], frames (4 s at 30 fps; chosen by measurement, see the
/// crate README).
pub const DEFAULT_WARMUP_FRAMES: usize = 120;

/// How [`crate::GruBaseline::predict_normalized_with`] cuts a recording.
///
/// ```
/// let c = gru_baseline::Chunking::default();
/// let chunks = c.plan(&vec![true; 5400])?;
/// assert_eq!(chunks.len(), 12);
/// assert_eq!((chunks[1].start, chunks[1].keep_from), (450 - c.warmup_frames, 450));
/// # Ok::<(), gru_baseline::GruError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Chunking {
    /// Sounding frames a chunk runs before its first kept output (none for the first chunk).
    pub warmup_frames: usize,
    /// Chunks run side by side in one pass (batch rows).
    pub rows_per_pass: usize,
    /// Longest kept part of a chunk, frames (bounds memory on long recordings).
    pub max_chunk_frames: usize,
}

impl Default for Chunking {
    /// 4 s warm-up, 12 rows (a register tile of six on each of two cores), chunks of at
    /// most 30 s.
    fn default() -> Self {
        Self {
            warmup_frames: DEFAULT_WARMUP_FRAMES,
            rows_per_pass: 12,
            max_chunk_frames: 900,
        }
    }
}

/// One chunk: input frames `start..end`, outputs kept from `keep_from` (`start` for the
/// first chunk; for the others, `warmup_frames` sounding frames earlier).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Chunk {
    /// First input frame (the GRU state is zero before it).
    pub start: usize,
    /// First output frame kept.
    pub keep_from: usize,
    /// One past the last frame.
    pub end: usize,
}

impl Chunk {
    /// Input frames, warm-up included.
    pub fn len(&self) -> usize {
        self.end - self.start
    }

    /// Whether the chunk has no frames.
    pub fn is_empty(&self) -> bool {
        self.end == self.start
    }
}

impl Chunking {
    /// Checks the values.
    pub fn validate(&self) -> Result<()> {
        if self.rows_per_pass == 0 || self.max_chunk_frames == 0 {
            return Err(GruError::Config(format!(
                "chunking needs at least one row per pass and one frame per chunk, got {self:?}"
            )));
        }
        Ok(())
    }

    /// The chunks of a recording whose frames are `sounding` (see [`sounding_frames`]), in
    /// time order: their kept parts tile the recording. A chunk keeps at least three
    /// warm-ups' worth of frames (so warm-ups cost at most about a third more work) and at
    /// most `max_chunk_frames`; a recording too short for two such chunks is one chunk,
    /// computed exactly. Each warm-up reaches back until it holds `warmup_frames` sounding
    /// frames, at most [`MAX_WARMUP_FACTOR`] × `warmup_frames`, or frame 0.
    pub fn plan(&self, sounding: &[bool]) -> Result<Vec<Chunk>> {
        self.validate()?;
        let frames = sounding.len();
        if frames == 0 {
            return Err(GruError::Empty("recording to chunk".into()));
        }
        let min_keep = (3 * self.warmup_frames).max(1);
        let keep = frames
            .div_ceil(self.rows_per_pass)
            .max(min_keep)
            .min(self.max_chunk_frames);
        let longest = MAX_WARMUP_FACTOR * self.warmup_frames;
        let mut out = Vec::with_capacity(frames.div_ceil(keep));
        let mut keep_from = 0;
        while keep_from < frames {
            let end = (keep_from + keep).min(frames);
            let mut start = keep_from;
            let mut heard = 0;
            while start > 0 && heard < self.warmup_frames && keep_from - start < longest {
                start -= 1;
                heard += usize::from(sounding[start]);
            }
            out.push(Chunk {
                start,
                keep_from,
                end,
            });
            keep_from = end;
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kept_parts_tile_the_recording() {
        let c = Chunking::default();
        for frames in [1, 89, 270, 271, 900, 1000, 5400, 5401, 20_000] {
            let chunks = c.plan(&vec![true; frames]).unwrap();
            assert_eq!(chunks[0].start, 0);
            assert_eq!(chunks[0].keep_from, 0);
            for pair in chunks.windows(2) {
                assert_eq!(pair[0].end, pair[1].keep_from);
                assert_eq!(pair[1].keep_from - pair[1].start, c.warmup_frames);
            }
            assert_eq!(chunks.last().unwrap().end, frames);
            assert!(chunks
                .iter()
                .all(|k| k.end - k.keep_from <= c.max_chunk_frames));
        }
        assert_eq!(c.plan(&[true; 200]).unwrap().len(), 1, "too short to chunk");
    }

    #[test]
    fn warm_ups_reach_back_over_silence_up_to_the_cap() {
        let c = Chunking {
            warmup_frames: 10,
            rows_per_pass: 4,
            max_chunk_frames: 100,
        };
        // 400 frames, keep 100 each; silence in 80..95 and everything before 300 from 200.
        let sounding: Vec<bool> = (0..400)
            .map(|t| !(80..95).contains(&t) && !(200..300).contains(&t))
            .collect();
        let chunks = c.plan(&sounding).unwrap();
        assert_eq!(chunks.len(), 4);
        assert_eq!(chunks[1].start, 100 - 10 - 15, "skips the 15 silent frames");
        assert_eq!(chunks[2].start, 200 - 10);
        assert_eq!(chunks[3].start, 300 - 30, "capped at 3 warm-ups");
    }

    #[test]
    fn rejects_empty_input_and_zero_sizes() {
        assert!(Chunking::default().plan(&[]).is_err());
        let bad = Chunking {
            rows_per_pass: 0,
            ..Chunking::default()
        };
        assert!(bad.plan(&[true; 100]).is_err());
    }
}
