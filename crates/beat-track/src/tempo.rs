//! Global tempo as `librosa.feature.tempo`: the mean over time of an autocorrelation
//! tempogram (8 s Hann windows, each normalised by its maximum), weighted by a log-normal
//! prior centred on `start_bpm`.

use rayon::prelude::*;
use realfft::num_complex::Complex;
use realfft::RealFftPlanner;
use serde::{Deserialize, Serialize};

/// Frames per parallel task.
const FRAMES_PER_TASK: usize = 512;

/// Parameters of [`estimate_tempo`]; the defaults are librosa's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TempoConfig {
    /// Centre of the prior in bpm.
    pub start_bpm: f64,
    /// Standard deviation of the prior in octaves.
    pub std_bpm: f64,
    /// Autocorrelation window in seconds.
    pub ac_size_s: f64,
    /// Only tempi below this are considered, in bpm.
    pub max_tempo_bpm: f64,
}

impl Default for TempoConfig {
    fn default() -> Self {
        Self {
            start_bpm: 120.0,
            std_bpm: 1.0,
            ac_size_s: 8.0,
            max_tempo_bpm: 320.0,
        }
    }
}

/// The mean normalised autocorrelation (lags `0..win_length`) of `envelope` in centred,
/// Hann-windowed frames of `win_length` values (librosa's `tempogram` averaged over time).
pub fn mean_tempogram(envelope: &[f32], win_length: usize) -> Vec<f64> {
    let n = envelope.len();
    if n == 0 || win_length == 0 {
        return vec![0.0; win_length];
    }
    let half = win_length / 2;
    // linear_ramp padding towards 0 on both sides.
    let mut padded = Vec::with_capacity(n + 2 * half);
    padded.extend((0..half).map(|k| f64::from(envelope[0]) * k as f64 / half as f64));
    padded.extend(envelope.iter().map(|&v| f64::from(v)));
    let last = f64::from(envelope[n - 1]);
    padded.extend((0..half).map(|k| last * (half - 1 - k) as f64 / half as f64));
    padded.resize(n + win_length, 0.0);
    let window: Vec<f64> = (0..win_length)
        .map(|i| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / win_length as f64).cos())
        .collect();
    let fft_len = smooth_even_at_least(2 * win_length);
    let mut planner = RealFftPlanner::<f32>::new();
    let forward = planner.plan_fft_forward(fft_len);
    let inverse = planner.plan_fft_inverse(fft_len);
    let starts: Vec<usize> = (0..n).step_by(FRAMES_PER_TASK).collect();
    let sums: Vec<Vec<f64>> = starts
        .into_par_iter()
        .map(|first| {
            let mut time = forward.make_input_vec();
            let mut spec = forward.make_output_vec();
            let mut scratch_f = forward.make_scratch_vec();
            let mut scratch_i = inverse.make_scratch_vec();
            let mut acf = inverse.make_output_vec();
            let mut sum = vec![0.0f64; win_length];
            for t in first..(first + FRAMES_PER_TASK).min(n) {
                time.fill(0.0);
                for ((d, &x), &w) in time.iter_mut().zip(&padded[t..t + win_length]).zip(&window) {
                    *d = (x * w) as f32;
                }
                if forward
                    .process_with_scratch(&mut time, &mut spec, &mut scratch_f)
                    .is_err()
                {
                    continue;
                }
                for z in spec.iter_mut() {
                    *z = Complex::new(z.norm_sqr(), 0.0);
                }
                if inverse
                    .process_with_scratch(&mut spec, &mut acf, &mut scratch_i)
                    .is_err()
                {
                    continue;
                }
                let peak = acf[..win_length].iter().fold(0.0f32, |m, v| m.max(v.abs()));
                // librosa's normalize leaves columns below `tiny` unscaled.
                let scale = if peak > f32::MIN_POSITIVE {
                    1.0 / f64::from(peak)
                } else {
                    1.0
                };
                for (s, v) in sum.iter_mut().zip(&acf[..win_length]) {
                    *s += f64::from(*v) * scale;
                }
            }
            sum
        })
        .collect();
    let mut mean = vec![0.0f64; win_length];
    for s in sums {
        for (m, v) in mean.iter_mut().zip(s) {
            *m += v;
        }
    }
    mean.iter_mut().for_each(|m| *m /= n as f64);
    mean
}

/// The smallest even number ≥ `n` whose only prime factors are 2, 3 and 5.
fn smooth_even_at_least(n: usize) -> usize {
    let mut m = n.max(2) + n % 2;
    loop {
        let mut r = m;
        for p in [2, 3, 5] {
            while r % p == 0 {
                r /= p;
            }
        }
        if r == 1 {
            return m;
        }
        m += 2;
    }
}

/// The tempo in bpm of an onset-strength curve with one value every `hop_length` samples
/// at `sample_rate_hz` (`librosa.feature.tempo` with `aggregate=np.mean`). Returns `None`
/// when no lag gives a tempo below `max_tempo_bpm`.
///
/// ```
/// // An impulse every 43 frames of 512 samples at 22 050 Hz (120.2 bpm): an impulse train
/// // correlates as well at twice the period, and librosa.feature.tempo also answers 60.09.
/// let env: Vec<f32> = (0..1000).map(|i| if i % 43 == 0 { 1.0 } else { 0.0 }).collect();
/// let bpm = beat_track::estimate_tempo(&env, 22_050, 512, &Default::default()).unwrap();
/// assert!((bpm - 60.0927).abs() < 1e-3, "{bpm}");
/// ```
pub fn estimate_tempo(
    envelope: &[f32],
    sample_rate_hz: u32,
    hop_length: usize,
    cfg: &TempoConfig,
) -> Option<f64> {
    let sr = f64::from(sample_rate_hz);
    let win_length = ((cfg.ac_size_s * sr).floor() as usize) / hop_length.max(1);
    if win_length < 2 {
        return None;
    }
    let tg = mean_tempogram(envelope, win_length);
    let bpm_of = |lag: usize| 60.0 * sr / (hop_length as f64 * lag as f64);
    (1..win_length)
        .filter(|&lag| bpm_of(lag) < cfg.max_tempo_bpm)
        .map(|lag| {
            let bpm = bpm_of(lag);
            let prior = -0.5 * ((bpm.log2() - cfg.start_bpm.log2()) / cfg.std_bpm).powi(2);
            (lag, (1e6 * tg[lag]).ln_1p() + prior)
        })
        .fold(
            None,
            |best: Option<(usize, f64)>, (lag, score)| match best {
                Some((_, s)) if s >= score => best,
                _ => Some((lag, score)),
            },
        )
        .map(|(lag, _)| bpm_of(lag))
}
