//! The training windows of arousal-labelled tracks: which 20-step windows an epoch draws,
//! their input, target and mask tensors (with an optional band shift), and the batch-norm
//! recalibration that passes an even spread of them through a trained network.

use candle_core::{Device, Tensor};

use crate::data::ArousalTrack;
use crate::error::Result;
use crate::model::{Config, EmotionNet};

/// Windows (at most) used by [`recalibrate_batch_norm`].
pub const CALIBRATION_WINDOWS: usize = 2048;

/// Re-estimates `net`'s batch-norm running statistics from up to [`CALIBRATION_WINDOWS`]
/// windows spread evenly over `tracks` (level-normalised as the network's configuration
/// says), passed with dropout off in batches of 64 (see
/// [`EmotionNet::recalibrate_batch_norm`]).
pub fn recalibrate_batch_norm(net: &EmotionNet, tracks: &[ArousalTrack]) -> Result<()> {
    let cfg = net.config();
    let tracks: Vec<ArousalTrack> = tracks
        .iter()
        .map(|t| ArousalTrack {
            mel_db: cfg.gain_norm.apply(t.mel_db.view()),
            ..t.clone()
        })
        .collect();
    let pads: Vec<f32> = tracks
        .iter()
        .map(|tr| tr.mel_db.iter().copied().fold(f32::INFINITY, f32::min))
        .collect();
    let windows = training_windows(&tracks, cfg.steps, 1);
    let every = windows.len().div_ceil(CALIBRATION_WINDOWS).max(1);
    let chosen: Vec<(usize, usize)> = windows.into_iter().step_by(every).collect();
    let batches = chosen
        .chunks(64)
        .map(|b| Ok(window_batch(&tracks, &pads, b, &[], cfg)?.0))
        .collect::<Result<Vec<Tensor>>>()?;
    net.recalibrate_batch_norm(&batches)
}

/// Every training window: `(track, first frame)`, `steps` frames every `hop` over the
/// annotated part of each track (the last one aligned with its end).
pub(crate) fn training_windows(
    tracks: &[ArousalTrack],
    steps: usize,
    hop: usize,
) -> Vec<(usize, usize)> {
    let mut windows = Vec::new();
    for (i, tr) in tracks.iter().enumerate() {
        let (first, len) = (tr.first_frame, tr.arousal.len());
        if len == 0 {
            continue;
        }
        let last = first + len.saturating_sub(steps);
        let mut s = first;
        while s <= last {
            windows.push((i, s));
            s += hop;
        }
        if (last - first) % hop != 0 {
            windows.push((i, last));
        }
    }
    windows
}

/// Inputs `(b, steps, bands)`, targets `(b, steps)` and target mask `(b, steps)` of the
/// windows `batch` (frames outside a track are its quietest value, unannotated steps masked),
/// window `k`'s bands shifted up by `shifts[k]` (edge bands repeated).
pub(crate) fn window_batch(
    tracks: &[ArousalTrack],
    pads: &[f32],
    batch: &[(usize, usize)],
    shifts: &[i64],
    cfg: &Config,
) -> Result<(Tensor, Tensor, Tensor)> {
    let (t, bands, b) = (cfg.steps, cfg.n_mels, batch.len());
    let mut x = vec![0.0f32; b * t * bands];
    let mut y = vec![0.0f32; b * t];
    let mut mask = vec![0.0f32; b * t];
    for (k, &(i, s)) in batch.iter().enumerate() {
        let tr = &tracks[i];
        net_core::frames::copy_frames(
            tr.mel_db.view(),
            s as isize,
            t,
            pads[i],
            &mut x[k * t * bands..][..t * bands],
        );
        let shift = shifts.get(k).copied().unwrap_or(0);
        if shift != 0 {
            net_core::frames::shift_bands(
                &mut x[k * t * bands..][..t * bands],
                bands,
                bands,
                shift,
            );
        }
        for j in 0..t {
            if let Some(&a) = (s + j)
                .checked_sub(tr.first_frame)
                .and_then(|o| tr.arousal.get(o))
            {
                y[k * t + j] = a;
                mask[k * t + j] = 1.0;
            }
        }
    }
    Ok((
        Tensor::from_vec(x, (b, t, bands), &Device::Cpu)?,
        Tensor::from_vec(y, (b, t), &Device::Cpu)?,
        Tensor::from_vec(mask, (b, t), &Device::Cpu)?,
    ))
}
