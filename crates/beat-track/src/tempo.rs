//! Global tempo as `librosa.feature.tempo`: the mean over time of an autocorrelation
//! tempogram (8 s Hann windows, each normalised by its maximum), weighted by a log-normal
//! prior centred on `start_bpm`.
//!
//! librosa averages a tempogram column at every onset frame (hop 11.6 ms) although
//! neighbouring 8 s windows differ by one frame in 344: the mean of such a slowly varying
//! column is estimated as well from every [`TempoConfig::frame_stride`]-th window (the
//! default 4 = 46 ms still averages ~86 windows per window length), at a quarter of the
//! cost. Windows are transformed two at a time ([`dsp_mel::fft::PairFft`]).

use dsp_mel::fft::{smooth_even_at_least, Complex, PairFft};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Windows per parallel task (even: windows go through the FFT in pairs).
const WINDOWS_PER_TASK: usize = 128;

/// Parameters of [`estimate_tempo`]; the defaults are librosa's, except that the tempogram
/// is averaged over every fourth window instead of every window.
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
    /// Onset frames between the averaged tempogram windows (1 = librosa's every frame).
    #[serde(default = "default_frame_stride")]
    pub frame_stride: usize,
}

fn default_frame_stride() -> usize {
    4
}

impl Default for TempoConfig {
    fn default() -> Self {
        Self {
            start_bpm: 120.0,
            std_bpm: 1.0,
            ac_size_s: 8.0,
            max_tempo_bpm: 320.0,
            frame_stride: default_frame_stride(),
        }
    }
}

/// The mean normalised autocorrelation (lags `0..win_length`) of `envelope` in centred,
/// Hann-windowed frames of `win_length` values (librosa's `tempogram` averaged over time).
pub fn mean_tempogram(envelope: &[f32], win_length: usize) -> Vec<f64> {
    mean_tempogram_strided(envelope, win_length, 1)
}

/// [`mean_tempogram`] over the windows centred on every `stride`-th frame (0 counts as 1).
pub fn mean_tempogram_strided(envelope: &[f32], win_length: usize, stride: usize) -> Vec<f64> {
    let n = envelope.len();
    if n == 0 || win_length == 0 {
        return vec![0.0; win_length];
    }
    let half = win_length / 2;
    // linear_ramp padding towards 0 on both sides.
    let mut padded: Vec<f32> = Vec::with_capacity(n + 2 * half);
    padded.extend((0..half).map(|k| (f64::from(envelope[0]) * k as f64 / half as f64) as f32));
    padded.extend_from_slice(envelope);
    let last = f64::from(envelope[n - 1]);
    padded.extend((0..half).map(|k| (last * (half - 1 - k) as f64 / half as f64) as f32));
    padded.resize(n + win_length, 0.0);
    let window: Vec<f32> = (0..win_length)
        .map(|i| (0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / win_length as f64).cos()) as f32)
        .collect();
    let fft = PairFft::<f32>::new(smooth_even_at_least(2 * win_length), true);
    let starts: Vec<usize> = (0..n).step_by(stride.max(1)).collect();
    let sums: Vec<Vec<f64>> = starts
        .par_chunks(WINDOWS_PER_TASK)
        .map(|task| {
            let mut buf = fft.buffers();
            let (mut acf_a, mut acf_b) = (vec![0.0f32; win_length], vec![0.0f32; win_length]);
            let mut sum = vec![0.0f64; win_length];
            for pair in task.chunks(2) {
                buf.data.fill(Complex::new(0.0, 0.0));
                let frame = |t: usize| padded[t..t + win_length].iter().zip(&window);
                for (d, (&x, &w)) in buf.data.iter_mut().zip(frame(pair[0])) {
                    d.re = x * w;
                }
                if let Some(&t) = pair.get(1) {
                    for (d, (&x, &w)) in buf.data.iter_mut().zip(frame(t)) {
                        d.im = x * w;
                    }
                }
                fft.acf_pair(&mut buf, &mut acf_a, &mut acf_b);
                add_normalised(&mut sum, &acf_a);
                if pair.len() == 2 {
                    add_normalised(&mut sum, &acf_b);
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
    mean.iter_mut().for_each(|m| *m /= starts.len() as f64);
    mean
}

/// `sum += acf / max|acf|` (librosa's normalize leaves columns below `tiny` unscaled).
fn add_normalised(sum: &mut [f64], acf: &[f32]) {
    let peak = acf.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    let scale = if peak > f32::MIN_POSITIVE {
        1.0 / f64::from(peak)
    } else {
        1.0
    };
    for (s, v) in sum.iter_mut().zip(acf) {
        *s += f64::from(*v) * scale;
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
    let win_length = tempogram_window(sample_rate_hz, hop_length, cfg)?;
    let tg = mean_tempogram_strided(envelope, win_length, cfg.frame_stride);
    tempo_from_tempogram(&tg, sample_rate_hz, hop_length, cfg)
}

/// The number of onset frames in the tempogram window of `cfg` (`None` when below 2).
pub(crate) fn tempogram_window(
    sample_rate_hz: u32,
    hop_length: usize,
    cfg: &TempoConfig,
) -> Option<usize> {
    let win_length =
        ((cfg.ac_size_s * f64::from(sample_rate_hz)).floor() as usize) / hop_length.max(1);
    (win_length >= 2).then_some(win_length)
}

/// The tempo of a lag in bpm.
pub(crate) fn bpm_of_lag(lag: usize, sample_rate_hz: u32, hop_length: usize) -> f64 {
    60.0 * f64::from(sample_rate_hz) / (hop_length as f64 * lag as f64)
}

/// librosa's choice on a mean tempogram: the lag maximising `ln(1 + 10⁶·tg) + prior`.
pub(crate) fn tempo_from_tempogram(
    tg: &[f64],
    sample_rate_hz: u32,
    hop_length: usize,
    cfg: &TempoConfig,
) -> Option<f64> {
    let bpm_of = |lag: usize| bpm_of_lag(lag, sample_rate_hz, hop_length);
    (1..tg.len())
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Clicks at a drifting period (rubato) with accents every fourth beat.
    fn rubato_clicks(frames: usize) -> Vec<f32> {
        let mut env = vec![0.05f32; frames];
        let (mut t, mut k) = (7.0f64, 0usize);
        while (t as usize) < frames {
            env[t as usize] = if k % 4 == 0 { 1.0 } else { 0.5 };
            t += 22.0 * (1.0 + 0.06 * (k as f64 / 9.0).sin());
            k += 1;
        }
        env
    }

    #[test]
    fn strided_mean_tempogram_is_close_to_the_full_one() {
        let env = rubato_clicks(3000);
        let full = mean_tempogram(&env, 384);
        let strided = mean_tempogram_strided(&env, 384, 4);
        let worst = full
            .iter()
            .zip(&strided)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f64, f64::max);
        assert!(worst < 5e-3, "largest difference {worst}");
        let argmax = |v: &[f64]| (20..v.len()).max_by(|&a, &b| v[a].total_cmp(&v[b]));
        assert_eq!(argmax(&full), argmax(&strided));
        let tempo = |stride| {
            let cfg = TempoConfig {
                frame_stride: stride,
                ..TempoConfig::default()
            };
            estimate_tempo(&env, 22_050, 512, &cfg)
        };
        assert_eq!(tempo(1), tempo(4));
    }

    #[test]
    fn empty_and_odd_window_counts() {
        assert_eq!(mean_tempogram(&[], 8), vec![0.0; 8]);
        // 5 windows at stride 2 → 3 windows, the last one alone in its FFT pair.
        let env = [0.0f32, 1.0, 0.0, 1.0, 0.0];
        let t = mean_tempogram_strided(&env, 4, 2);
        assert!((t[0] - 1.0).abs() < 1e-6, "{t:?}");
    }
}
