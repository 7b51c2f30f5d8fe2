//! Stride-1 inference over a whole recording: one probability of "bow change" per frame.
//!
//! The spectrogram is cut into equal tiles of at most [`TILE_WINDOWS`] windows (plus the
//! window's context, [`tile_windows`]) and each tile goes through the phase tree of
//! [`BowingNet::sequence_logits_inference`], so the convolutions run about once per frame
//! instead of once per window.

use candle_core::{Device, Tensor};
use ndarray::ArrayView2;
use net_core::frames::{check_mel, copy_frames, pad_value};
use rayon::prelude::*;

use crate::error::{NetError, Result};
use crate::model::{window_start, BowingNet, PHASES};

/// Most windows (frames) classified per tile.
pub const TILE_WINDOWS: usize = 2048;

/// Windows per tile for a recording of `frames` frames: as few tiles as [`TILE_WINDOWS`]
/// allows, of equal size rounded up to a multiple of [`PHASES`], so the last tile is not
/// mostly padding (180 s in tiles of 2048 would compute 14 % more frames than it has).
///
/// ```
/// use bowing_net::infer::tile_windows;
/// assert_eq!(tile_windows(5400), 1800); // 3 tiles
/// assert_eq!(tile_windows(2049), 1032); // 2 tiles
/// assert_eq!(tile_windows(100), 104);
/// ```
pub fn tile_windows(frames: usize) -> usize {
    let tiles = frames.div_ceil(TILE_WINDOWS).max(1);
    frames.div_ceil(tiles).next_multiple_of(PHASES).max(PHASES)
}
/// Extra frames after the last window of a sequence so that every pool phase still has all
/// of its windows (the phase tree truncates phases to a common length).
pub const SEQUENCE_SLACK: usize = 2 * PHASES;

/// Frames of input a sequence needs to classify `windows` windows.
pub fn sequence_frames(net: &BowingNet, windows: usize) -> usize {
    windows + net.config().window_frames - 1 + SEQUENCE_SLACK
}

/// Per-frame probabilities that a bow change happens at that frame, for a `(frames, 128)`
/// mel dB spectrogram (30 fps). Frame `t` is classified from the window
/// `t − 30 .. t + 29`; frames outside the recording count as silence.
pub fn frame_probabilities(net: &BowingNet, mel: ArrayView2<f32>) -> Result<Vec<f32>> {
    let cfg = net.config();
    check_mel(mel, cfg.n_mels)?;
    let frames = mel.nrows();
    let pad = pad_value(mel);
    let center = cfg.center_offset() as isize;
    let tile_len = tile_windows(frames);
    let seq_len = sequence_frames(net, tile_len);
    let tiles = frames.div_ceil(tile_len);
    let bands = cfg.n_mels;
    // Tiles are independent: run them on all cores (the ops inside stay parallel too).
    let results: Vec<Result<Vec<Vec<f32>>>> = (0..tiles)
        .into_par_iter()
        .map(|tile| {
            let mut buf = vec![0.0f32; seq_len * bands];
            copy_frames(
                mel,
                (tile * tile_len) as isize - center,
                seq_len,
                pad,
                &mut buf,
            );
            let x = Tensor::from_vec(buf, (1, seq_len, bands), &Device::Cpu)?;
            let logits = net.sequence_logits_inference(&x)?;
            Ok(BowingNet::change_probability(&logits)?.to_vec2::<f32>()?)
        })
        .collect();
    let mut out = vec![f32::NAN; frames];
    for (tile, probs) in results.into_iter().enumerate() {
        let start = tile * tile_len;
        for (row, values) in probs?.iter().enumerate() {
            for (step, &p) in values.iter().enumerate() {
                let (_, s) = window_start(row, step, 1);
                if s < tile_len && start + s < frames {
                    out[start + s] = p;
                }
            }
        }
    }
    if out.iter().any(|p| p.is_nan()) {
        return Err(NetError::Input(
            "internal: a frame was not covered by the phase tree".into(),
        ));
    }
    Ok(out)
}

/// The same probabilities computed window by window with [`BowingNet::forward_t`] (slow;
/// the reference the fast path is tested against), for the frames in `range`.
pub fn frame_probabilities_per_window(
    net: &BowingNet,
    mel: ArrayView2<f32>,
    range: std::ops::Range<usize>,
) -> Result<Vec<f32>> {
    let cfg = net.config();
    check_mel(mel, cfg.n_mels)?;
    let pad = pad_value(mel);
    let (w, bands) = (cfg.window_frames, cfg.n_mels);
    let range = range.start.min(mel.nrows())..range.end.min(mel.nrows());
    let n = range.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let mut buf = vec![0.0f32; n * w * bands];
    for (k, chunk) in buf.chunks_exact_mut(w * bands).enumerate() {
        let t = range.start + k;
        copy_frames(
            mel,
            t as isize - cfg.center_offset() as isize,
            w,
            pad,
            chunk,
        );
    }
    let x = Tensor::from_vec(buf, (n, w, bands), &Device::Cpu)?;
    Ok(BowingNet::change_probability(&net.forward_t(&x, false)?)?.to_vec1::<f32>()?)
}
