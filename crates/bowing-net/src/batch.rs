//! Training batches for the phase tree ([`crate::model::BowingNet::sequence_logits`]): each
//! epoch tiles every training recording with runs of consecutive windows ("sequences") from
//! a random offset, shuffles them, and groups them into batches; each frame gets a target
//! (widened labels) and a loss weight (class balance, hard negatives); inputs can be
//! augmented.

use ndarray::ArrayView2;
use net_core::rng::Rng;
use serde::{Deserialize, Serialize};

use crate::data::Recording;
use crate::model::window_start;
use net_core::frames::copy_frames;

/// Random changes to each training sequence's spectrogram (one draw per sequence).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Augment {
    /// A level change uniform in ±`gain_db` dB is added to every value (recording level
    /// is arbitrary: the corpus's own gain spread is −12…0 dB).
    pub gain_db: f32,
    /// The spectrum is shifted by up to ±`band_shift` mel bands (edge bands repeated):
    /// small tuning and timbre differences.
    pub band_shift: usize,
}

impl Default for Augment {
    fn default() -> Self {
        Self {
            gain_db: 6.0,
            band_shift: 0,
        }
    }
}

impl Augment {
    /// No augmentation.
    pub const NONE: Augment = Augment {
        gain_db: 0.0,
        band_shift: 0,
    };
}

/// How frames are labelled and weighted in the loss.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weighting {
    /// Frames on each side of a change also labelled "change".
    pub label_radius_frames: usize,
    /// Weight of a positive frame (negatives weigh 1).
    pub positive_weight: f32,
    /// Weight of a negative frame within ±`label_radius_frames` of a slurred note change
    /// (a new note without a bow change: the hard negatives).
    pub slur_weight: f32,
}

/// Per-frame targets (0/1) and loss weights of one recording.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameLabels {
    /// 1 within ±radius of a bow change.
    pub targets: Vec<u8>,
    /// The frame's weight in the loss.
    pub weights: Vec<f32>,
}

/// Frames that are positive after widening each change by ±`radius`.
pub fn positive_frames(rec: &Recording, radius: usize) -> Vec<u8> {
    let n = rec.mel_db.nrows();
    let mut out = vec![0u8; n];
    for &c in &rec.changes {
        let end = (c + radius + 1).min(n);
        if let Some(span) = out.get_mut(c.saturating_sub(radius)..end) {
            span.fill(1);
        }
    }
    out
}

/// Targets and weights of `rec` ([`Weighting`]).
///
/// ```
/// use bowing_net::batch::{frame_labels, Weighting};
/// let rec = bowing_net::data::Recording {
///     name: "r".into(), group: "g".into(), mel_db: ndarray::Array2::zeros((12, 4)),
///     changes: vec![3], onsets: vec![3, 8], slurred: vec![8], strokes: vec![], strings: vec![],
/// };
/// let w = Weighting { label_radius_frames: 1, positive_weight: 4.0, slur_weight: 2.0 };
/// let l = frame_labels(&rec, &w);
/// assert_eq!(l.targets, vec![0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0]);
/// assert_eq!(l.weights[3], 4.0);
/// assert_eq!(&l.weights[6..11], &[1.0, 2.0, 2.0, 2.0, 1.0]);
/// ```
pub fn frame_labels(rec: &Recording, w: &Weighting) -> FrameLabels {
    let targets = positive_frames(rec, w.label_radius_frames);
    let mut weights: Vec<f32> = targets
        .iter()
        .map(|&y| if y == 1 { w.positive_weight } else { 1.0 })
        .collect();
    let r = w.label_radius_frames;
    for &s in &rec.slurred {
        for f in s.saturating_sub(r)..(s + r + 1).min(targets.len()) {
            if targets[f] == 0 {
                weights[f] = w.slur_weight;
            }
        }
    }
    FrameLabels { targets, weights }
}

/// The sequences of one epoch, shuffled: `(recording, first classified frame)`; each
/// recording is tiled by runs of `windows` frames from a random offset (the first run may
/// start before the recording: those frames are masked out of the loss).
pub fn plan_epoch(frames: &[usize], windows: usize, rng: &mut Rng) -> Vec<(usize, isize)> {
    let n_seq = windows.max(1) as isize;
    let mut seqs = Vec::new();
    for (ri, &len) in frames.iter().enumerate() {
        let offset = (rng.next_u64() % n_seq as u64) as isize;
        let mut start = if offset > 0 { offset - n_seq } else { 0 };
        while start < len as isize {
            seqs.push((ri, start));
            start += n_seq;
        }
    }
    for i in (1..seqs.len()).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        seqs.swap(i, j);
    }
    seqs
}

/// Copies the input of one sequence (`seq_len` frames from frame `first`, padded with
/// `pad`) into `dst`, augmented by a draw from `rng`.
pub fn sequence_input(
    mel: ArrayView2<f32>,
    first: isize,
    pad: f32,
    augment: &Augment,
    rng: &mut Rng,
    dst: &mut [f32],
) {
    let bands = mel.ncols();
    let seq_len = dst.len() / bands.max(1);
    copy_frames(mel, first, seq_len, pad, dst);
    if augment.band_shift > 0 {
        let span = 2 * augment.band_shift as u64 + 1;
        let shift = (rng.next_u64() % span) as isize - augment.band_shift as isize;
        if shift != 0 {
            let mut row_copy = vec![0.0f32; bands];
            for row in dst.chunks_exact_mut(bands) {
                row_copy.copy_from_slice(row);
                for (k, v) in row.iter_mut().enumerate() {
                    let src = (k as isize - shift).clamp(0, bands as isize - 1) as usize;
                    *v = row_copy[src];
                }
            }
        }
    }
    if augment.gain_db > 0.0 {
        let gain = rng.uniform(-f64::from(augment.gain_db), f64::from(augment.gain_db)) as f32;
        dst.iter_mut().for_each(|v| *v += gain);
    }
}

/// Targets and weights of every logit of a batch (`rows × windows`, laid out as
/// [`window_start`] says) for the sequences `batch` of `classified` windows each; windows
/// outside their recording or beyond `classified` get weight 0.
pub fn batch_targets(
    labels: &[FrameLabels],
    batch: &[(usize, isize)],
    rows: usize,
    windows: usize,
    classified: usize,
) -> (Vec<u32>, Vec<f32>) {
    let mut targets = vec![0u32; rows * windows];
    let mut weights = vec![0.0f32; rows * windows];
    for row in 0..rows {
        for j in 0..windows {
            let (k, s) = window_start(row, j, batch.len());
            let (ri, start) = batch[k];
            let frame = start + s as isize;
            let l = &labels[ri];
            if s < classified && frame >= 0 && (frame as usize) < l.targets.len() {
                targets[row * windows + j] = u32::from(l.targets[frame as usize]);
                weights[row * windows + j] = l.weights[frame as usize];
            }
        }
    }
    (targets, weights)
}
