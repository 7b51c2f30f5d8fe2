//! Training crops: a stretch of a recording resampled in time (tempo augmentation), with
//! per-frame classes and loss weights (a beat's neighbours count half, Böck et al.).

use net_core::rng::Rng;

use crate::data::Recording;
use crate::features::FPS;

/// Classes and weights of one crop.
#[derive(Debug, Clone, PartialEq)]
pub struct Targets {
    /// 0 no beat, 1 beat, 2 downbeat, per frame.
    pub classes: Vec<u32>,
    /// Loss weight per frame (0 beyond the recording's end).
    pub weights: Vec<f32>,
}

/// Per-frame targets for `frames` frames whose frame `k` is source time
/// `(start + k·stretch) / FPS`; frames at `valid..` weigh 0. Exact beat frames weigh 1, their
/// two neighbours `neighbour_weight`.
pub fn targets(
    rec: &Recording,
    start: f64,
    stretch: f64,
    frames: usize,
    valid: usize,
    neighbour_weight: f32,
) -> Targets {
    let mut classes = vec![0u32; frames];
    let mut weights: Vec<f32> = (0..frames)
        .map(|k| if k < valid { 1.0 } else { 0.0 })
        .collect();
    for (times, class) in [(&rec.beats_s, 1), (&rec.downbeats_s, 2)] {
        // Downbeats are beats too: their pass comes second and overrides.
        let mut exact = vec![false; frames];
        for &t in times {
            let f = ((t * FPS - start) / stretch).round();
            if !(f > -2.0 && f < frames as f64 + 1.0) {
                continue;
            }
            let f = f as isize;
            for d in [-1isize, 0, 1] {
                let k = f + d;
                if k < 0 || k as usize >= valid {
                    continue;
                }
                let k = k as usize;
                if d == 0 {
                    classes[k] = class;
                    weights[k] = 1.0;
                    exact[k] = true;
                } else if !exact[k] {
                    classes[k] = class;
                    weights[k] = neighbour_weight;
                }
            }
        }
    }
    Targets { classes, weights }
}

/// A crop: `frames` input frames (row-major, `frames × features`) and its targets.
#[derive(Debug, Clone)]
pub struct Crop {
    /// Input frames.
    pub input: Vec<f32>,
    /// Targets.
    pub targets: Targets,
}

/// A random crop of `rec` of `frames` output frames with a time stretch drawn from
/// `stretch` (source frames per output frame); frames past the end repeat the recording's
/// per-feature minimum and weigh 0.
pub fn random_crop(
    rec: &Recording,
    frames: usize,
    stretch: (f64, f64),
    neighbour_weight: f32,
    rng: &mut Rng,
) -> Crop {
    let s = if stretch.1 > stretch.0 {
        rng.uniform(stretch.0, stretch.1)
    } else {
        stretch.0
    };
    let len = rec.frames();
    let span = frames as f64 * s;
    let max_start = (len as f64 - span).max(0.0);
    let start = rng.uniform(0.0, max_start.max(1e-9)).min(max_start);
    let f = rec.features.ncols();
    let pad: Vec<f32> = (0..f)
        .map(|c| {
            rec.features
                .column(c)
                .iter()
                .copied()
                .fold(f32::INFINITY, f32::min)
        })
        .collect();
    let mut input = vec![0.0f32; frames * f];
    let mut valid = frames;
    for (k, dst) in input.chunks_exact_mut(f).enumerate() {
        let src = start + k as f64 * s;
        let i = src.floor() as usize;
        if i + 1 >= len {
            if valid == frames {
                valid = k;
            }
            dst.copy_from_slice(&pad);
            continue;
        }
        let w = (src - i as f64) as f32;
        let (a, b) = (rec.features.row(i), rec.features.row(i + 1));
        for ((d, x), y) in dst.iter_mut().zip(a).zip(b) {
            *d = x + w * (y - x);
        }
    }
    let targets = targets(rec, start, s, frames, valid, neighbour_weight);
    Crop { input, targets }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::Array2;

    fn rec() -> Recording {
        Recording {
            name: "r".into(),
            features: Array2::from_shape_fn((300, 3), |(t, c)| (t * 3 + c) as f32),
            beats_s: vec![1.0, 2.0, 3.0, 4.0],
            downbeats_s: vec![1.0, 3.0],
        }
    }

    #[test]
    fn targets_mark_beats_downbeats_and_neighbours() {
        let t = targets(&rec(), 0.0, 1.0, 200, 200, 0.5);
        assert_eq!(t.classes[30], 2);
        assert_eq!(t.classes[29], 2);
        assert_eq!(t.weights[29], 0.5);
        assert_eq!(t.classes[60], 1);
        assert_eq!(t.weights[60], 1.0);
        assert_eq!(t.classes[45], 0);
        // Stretched by 2: beat at 2 s (frame 60) is output frame 30.
        let t = targets(&rec(), 0.0, 2.0, 100, 100, 0.5);
        assert_eq!(t.classes[30], 1);
        assert_eq!(t.classes[15], 2);
    }

    #[test]
    fn crops_interpolate_and_mask_the_end() {
        let mut rng = Rng::new(1);
        let c = random_crop(&rec(), 400, (1.0, 1.0), 0.5, &mut rng);
        assert_eq!(c.input.len(), 400 * 3);
        assert_eq!(c.input[3 * 10], 30.0);
        assert!(c.targets.weights[350] == 0.0 && c.targets.weights[10] == 1.0);
        let c = random_crop(&rec(), 100, (0.8, 1.25), 0.5, &mut rng);
        assert!(c.targets.weights.iter().all(|w| *w > 0.0));
    }
}
