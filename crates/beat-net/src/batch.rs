//! Training crops: a stretch of a recording resampled in time (tempo augmentation), with
//! per-frame classes and loss weights (a beat's neighbours count half, Böck et al.), and
//! quiet crops (silence or faint stationary noise, no beat anywhere) that teach the network
//! to stay low where nothing is played.

use ndarray::Array2;
use net_core::rng::Rng;

use crate::data::Recording;
use crate::error::Result;
use crate::features::{frame_features, EXTRA_FEATURES, FPS, RANGE_DB};

/// The mel level (dB) of digital silence in a quiet crop (what the analysis front end gives
/// for zeros, and what the pretrained test feeds the network).
pub const SILENCE_DB: f32 = -100.0;
/// The range of a noise crop's mean level (dB, the mel's scale): from just above silence
/// to a faint hiss far below a played note.
pub const NOISE_LEVEL_DB: (f64, f64) = (-100.0, -50.0);
/// The largest spectral tilt of a noise crop (dB from the lowest to the highest band).
pub const NOISE_MAX_TILT_DB: f64 = 30.0;
/// The range of a noise crop's frame-to-frame standard deviation per band (dB).
pub const NOISE_SPREAD_DB: (f64, f64) = (0.5, 4.0);

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

/// What a quiet crop holds (see [`quiet_mel`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Quiet {
    /// Every band at [`SILENCE_DB`].
    Silence,
    /// Stationary noise: band `b` of `bands` at `level_db − tilt_db·b/(bands−1)` plus an
    /// independent normal deviation of `spread_db` per frame and band.
    Noise {
        /// Mean level of the lowest band (dB).
        level_db: f32,
        /// Fall from the lowest to the highest band (dB).
        tilt_db: f32,
        /// Standard deviation per frame and band (dB).
        spread_db: f32,
    },
}

impl Quiet {
    /// Silence or noise with equal chance; a noise's level, tilt and spread are drawn
    /// uniformly from [`NOISE_LEVEL_DB`], `0..`[`NOISE_MAX_TILT_DB`] and [`NOISE_SPREAD_DB`].
    pub fn draw(rng: &mut Rng) -> Self {
        if rng.chance(0.5) {
            return Quiet::Silence;
        }
        Quiet::Noise {
            level_db: rng.uniform(NOISE_LEVEL_DB.0, NOISE_LEVEL_DB.1) as f32,
            tilt_db: rng.uniform(0.0, NOISE_MAX_TILT_DB) as f32,
            spread_db: rng.uniform(NOISE_SPREAD_DB.0, NOISE_SPREAD_DB.1) as f32,
        }
    }
}

/// The mel dB spectrogram `(frames, bands)` of a quiet crop; noise deviations come from
/// `rng` (silence draws nothing).
pub fn quiet_mel(kind: Quiet, frames: usize, bands: usize, rng: &mut Rng) -> Array2<f32> {
    match kind {
        Quiet::Silence => Array2::from_elem((frames, bands), SILENCE_DB),
        Quiet::Noise {
            level_db,
            tilt_db,
            spread_db,
        } => {
            let step = tilt_db / bands.saturating_sub(1).max(1) as f32;
            Array2::from_shape_fn((frames, bands), |(_, b)| {
                level_db - step * b as f32 + spread_db * rng.normal() as f32
            })
        }
    }
}

/// A quiet crop of `frames` frames over `bands` mel bands: [`quiet_mel`] of a
/// [`Quiet::draw`] run through [`frame_features`] as a recording of its own (its reference
/// level floored as any silent recording's), every frame of class 0 (no beat) at weight 1.
/// Fails only when `frames` or `bands` is 0.
pub fn quiet_crop(frames: usize, bands: usize, rng: &mut Rng) -> Result<Crop> {
    let kind = Quiet::draw(rng);
    let mel = quiet_mel(kind, frames, bands, rng);
    let input = frame_features(mel.view())?.into_iter().collect();
    Ok(Crop {
        input,
        targets: Targets {
            classes: vec![0; frames],
            weights: vec![1.0; frames],
        },
    })
}

/// Hears a crop of input frames (`features` values per frame: the mel bands, then the flux and
/// the loudest band, as [`frame_features`] makes them) through a fixed equaliser `curve` (dB
/// per band, e.g. [`net_core::frames::random_eq_curve`]): a violin or a recording chain the
/// corpus lacks. Bands at the floor (−[`RANGE_DB`]) stay there; the crop moves as a whole so
/// that its loudest frame keeps its level (the input is relative to the recording's loudest
/// frames), values stay within ±[`RANGE_DB`], and the loudest band is recomputed. The flux is
/// kept: a fixed gain per band does not change how a band rises from frame to frame. Nothing
/// happens when `curve` does not have one value per band.
///
/// ```
/// // Two frames of 3 bands, flux and loudest band (dB/10).
/// let mut crop = [-10.0f32, -20.0, -80.0, 0.0, -1.0, -30.0, -5.0, -80.0, 2.0, -0.5];
/// beat_net::batch::equalise(&mut crop, 5, &[0.0, 10.0, 6.0]);
/// // Band 1 gains 10 dB; the loudest frame (−5 → +5 dB) is moved back to −5 dB.
/// assert_eq!(crop, [-20.0, -20.0, -80.0, 0.0, -2.0, -40.0, -5.0, -80.0, 2.0, -0.5]);
/// ```
pub fn equalise(crop: &mut [f32], features: usize, curve: &[f32]) {
    let bands = features.saturating_sub(EXTRA_FEATURES);
    if bands == 0 || curve.len() != bands {
        return;
    }
    net_core::frames::equalise_bands(crop, features, bands, curve, -RANGE_DB, RANGE_DB);
    for row in crop.chunks_exact_mut(features) {
        row[bands + 1] = row[..bands].iter().copied().fold(-RANGE_DB, f32::max) / 10.0;
    }
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
    fn equalising_real_features_keeps_the_flux_the_floor_and_the_loudest_level() {
        let mel = Array2::from_shape_fn((40, 16), |(t, b)| {
            if b > 12 {
                -200.0
            } else {
                -20.0 - b as f32 - if t % 5 == 0 { 0.0 } else { 12.0 }
            }
        });
        let input = frame_features(mel.view()).unwrap();
        let plain: Vec<f32> = input.iter().copied().collect();
        let mut flat = plain.clone();
        equalise(&mut flat, 18, &[0.0; 16]);
        assert_eq!(flat, plain);
        let curve = net_core::frames::random_eq_curve(&mut Rng::new(4), 16, 6.0);
        let mut heard = plain.clone();
        equalise(&mut heard, 18, &curve);
        assert_ne!(heard, plain);
        let top = |x: &[f32]| x.chunks(18).map(|r| r[17]).fold(f32::MIN, f32::max);
        assert!((top(&heard) - top(&plain)).abs() < 1e-5);
        for (h, p) in heard.chunks(18).zip(plain.chunks(18)) {
            assert_eq!(h[16], p[16], "flux kept");
            assert!(h[13..16].iter().all(|v| *v == -RANGE_DB), "floor kept");
        }
        let mut short = plain.clone();
        equalise(&mut short, 18, &curve[..15]);
        assert_eq!(short, plain, "a curve of the wrong length changes nothing");
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

    #[test]
    fn quiet_crops_have_no_beats_and_the_intended_mel() {
        let mut rng = Rng::new(7);
        let silence = quiet_mel(Quiet::Silence, 20, 8, &mut rng);
        assert!(silence.iter().all(|v| *v == SILENCE_DB));
        let kind = Quiet::Noise {
            level_db: -80.0,
            tilt_db: 14.0,
            spread_db: 2.0,
        };
        let noise = quiet_mel(kind, 2000, 8, &mut rng);
        for b in 0..8 {
            let col = noise.column(b);
            let mean = col.sum() / 2000.0;
            let sd = (col.mapv(|v| (v - mean).powi(2)).sum() / 2000.0).sqrt();
            assert!((mean - (-80.0 - 2.0 * b as f32)).abs() < 0.2, "{b}: {mean}");
            assert!((sd - 2.0).abs() < 0.15, "{b}: {sd}");
        }
        let (mut saw_silence, mut saw_noise) = (false, false);
        for _ in 0..40 {
            let mut a = Rng::new(rng.next_u64());
            let mut b = a.clone();
            let crop = quiet_crop(50, 8, &mut a).unwrap();
            assert_eq!(crop.targets.classes, vec![0; 50]);
            assert_eq!(crop.targets.weights, vec![1.0; 50]);
            // The input is exactly the features of the drawn mel, and the draw is seeded.
            let kind = Quiet::draw(&mut b);
            let mel = quiet_mel(kind, 50, 8, &mut b);
            let want: Vec<f32> = frame_features(mel.view()).unwrap().into_iter().collect();
            assert_eq!(crop.input, want);
            match kind {
                Quiet::Silence => {
                    saw_silence = true;
                    // −100 dB against the −70 dB reference floor: −30 everywhere, no flux.
                    assert!(crop
                        .input
                        .chunks(10)
                        .all(|r| r[..8].iter().all(|v| *v == -30.0)
                            && r[8] == 0.0
                            && r[9] == -3.0));
                }
                Quiet::Noise { level_db, .. } => {
                    saw_noise = true;
                    assert!((-100.0..-50.0).contains(&level_db));
                }
            }
        }
        assert!(saw_silence && saw_noise);
        assert!(quiet_crop(0, 8, &mut rng).is_err());
    }
}
