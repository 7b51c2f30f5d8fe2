//! Per-frame YIN: the cumulative-mean-normalised difference function (computed from an FFT
//! autocorrelation), parabolic refinement, and pYIN's probabilistic candidates.

use std::sync::Arc;

use dsp_mel::fft::{smooth_even_at_least, Complex, ComplexToReal, Planner, RealToComplex};
use rayon::prelude::*;

use crate::config::PitchConfig;
use crate::prior::{boltzmann_pmf, ThresholdPrior};

/// Frames per parallel task: amortises the scratch buffers, balances the cores.
const FRAMES_PER_TASK: usize = 256;

/// One f0 candidate of a frame: a trough of the YIN function with its pYIN probability.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Candidate {
    /// Pitch bin (0 = `fmin_hz`).
    pub bin: u32,
    /// Probability that this trough is the period.
    pub prob: f32,
    /// The candidate's exact frequency (parabolically refined period), in Hz.
    pub f0_hz: f32,
}

/// The observations of all frames: candidates stored flat, frame `t` owning
/// `candidates[offsets[t]..offsets[t + 1]]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Observations {
    pub candidates: Vec<Candidate>,
    pub offsets: Vec<usize>,
    /// Sum of the candidates' probabilities, clipped to [0, 1] (librosa's `voiced_prob`).
    pub voiced_prob: Vec<f32>,
}

impl Observations {
    /// Number of frames.
    pub fn len(&self) -> usize {
        self.voiced_prob.len()
    }

    /// The candidates of frame `t`.
    pub fn frame(&self, t: usize) -> &[Candidate] {
        &self.candidates[self.offsets[t]..self.offsets[t + 1]]
    }
}

/// The planned YIN front end: FFT plans and priors built once, reused for every frame.
pub(crate) struct Yin {
    cfg: PitchConfig,
    fft_len: usize,
    forward: Arc<dyn RealToComplex<f32>>,
    inverse: Arc<dyn ComplexToReal<f32>>,
    prior: ThresholdPrior,
    bins_per_octave: f64,
    n_bins: usize,
}

/// Per-task buffers, allocated once per task and reused frame after frame.
struct Scratch {
    time: Vec<f32>,
    spectrum: Vec<Complex<f32>>,
    fwd_scratch: Vec<Complex<f32>>,
    inv_scratch: Vec<Complex<f32>>,
    acf: Vec<f32>,
    cmnd: Vec<f64>,
    troughs: Vec<usize>,
    by_height: Vec<usize>,
    member: Vec<bool>,
    probs: Vec<f64>,
}

impl Yin {
    pub fn new(cfg: &PitchConfig) -> Self {
        let fft_len = smooth_even_at_least(cfg.frame_length + cfg.max_period() + 1);
        let mut planner = Planner::<f32>::new();
        Self {
            forward: planner.real_forward(fft_len),
            inverse: planner.real_inverse(fft_len),
            fft_len,
            prior: ThresholdPrior::new(
                cfg.n_thresholds,
                cfg.beta_parameters.0,
                cfg.beta_parameters.1,
            ),
            bins_per_octave: 12.0 * cfg.bins_per_semitone() as f64,
            n_bins: cfg.n_pitch_bins(),
            cfg: cfg.clone(),
        }
    }

    fn scratch(&self) -> Scratch {
        let n_lags = self.cfg.max_period() - self.cfg.min_period() + 1;
        Scratch {
            time: self.forward.make_input_vec(),
            spectrum: self.forward.make_output_vec(),
            fwd_scratch: self.forward.make_scratch_vec(),
            inv_scratch: self.inverse.make_scratch_vec(),
            acf: self.inverse.make_output_vec(),
            cmnd: vec![0.0; n_lags],
            troughs: Vec::with_capacity(n_lags),
            by_height: Vec::with_capacity(n_lags),
            member: Vec::with_capacity(n_lags),
            probs: Vec::with_capacity(n_lags),
        }
    }

    /// Observations of every centred frame of `samples` (1 + len / hop frames).
    pub fn observe(&self, samples: &[f32]) -> Observations {
        let n_frames = 1 + samples.len() / self.cfg.hop_length;
        let tasks: Vec<(Vec<Candidate>, Vec<usize>, Vec<f32>)> = (0..n_frames)
            .step_by(FRAMES_PER_TASK)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|first| {
                let last = (first + FRAMES_PER_TASK).min(n_frames);
                let mut s = self.scratch();
                let mut cands = Vec::with_capacity((last - first) * 8);
                let mut counts = Vec::with_capacity(last - first);
                let mut voiced = Vec::with_capacity(last - first);
                for t in first..last {
                    let before = cands.len();
                    let vp = self.frame(samples, t, &mut s, &mut cands);
                    counts.push(cands.len() - before);
                    voiced.push(vp);
                }
                (cands, counts, voiced)
            })
            .collect();
        let mut obs = Observations {
            candidates: Vec::with_capacity(tasks.iter().map(|t| t.0.len()).sum()),
            offsets: Vec::with_capacity(n_frames + 1),
            voiced_prob: Vec::with_capacity(n_frames),
        };
        obs.offsets.push(0);
        for (cands, counts, voiced) in tasks {
            obs.candidates.extend_from_slice(&cands);
            for c in counts {
                let last = obs.offsets.last().copied().unwrap_or(0);
                obs.offsets.push(last + c);
            }
            obs.voiced_prob.extend_from_slice(&voiced);
        }
        obs
    }

    /// Candidates of frame `t` appended to `out`; returns the frame's voiced probability.
    fn frame(&self, samples: &[f32], t: usize, s: &mut Scratch, out: &mut Vec<Candidate>) -> f32 {
        let n = self.cfg.frame_length;
        let start = (t * self.cfg.hop_length) as isize - (n / 2) as isize;
        s.time.fill(0.0);
        let lo = start.max(0) as usize;
        let hi = ((start + n as isize).max(0) as usize).min(samples.len());
        if lo < hi {
            let at = (lo as isize - start) as usize;
            s.time[at..at + hi - lo].copy_from_slice(&samples[lo..hi]);
        }
        // Energy terms need the frame before the FFT overwrites it.
        let max_p = self.cfg.max_period();
        let min_p = self.cfg.min_period();
        // d(k) = 2 (r0 − rk) − Σ_{m<k} y[m]²: the first max_p prefix sums of the energy
        // (kept in `probs`, which is free until the candidates are scored).
        let mut cum = 0.0f64;
        s.probs.clear();
        for &y in &s.time[..max_p] {
            cum += f64::from(y) * f64::from(y);
            s.probs.push(cum);
        }
        if self
            .forward
            .process_with_scratch(&mut s.time, &mut s.spectrum, &mut s.fwd_scratch)
            .is_err()
        {
            return 0.0;
        }
        for z in s.spectrum.iter_mut() {
            *z = Complex::new(z.re * z.re + z.im * z.im, 0.0);
        }
        // The power spectrum is real, so the inverse transform cannot reject it.
        let _ = self
            .inverse
            .process_with_scratch(&mut s.spectrum, &mut s.acf, &mut s.inv_scratch);
        let scale = 1.0 / self.fft_len as f64;
        let r0 = f64::from(s.acf[0]) * scale;
        // Cumulative mean normalised difference for lags min_p..=max_p.
        let mut running = 0.0f64;
        for k in 1..=max_p {
            let rk = f64::from(s.acf[k]) * scale;
            let d = 2.0 * (r0 - rk) - s.probs[k - 1];
            running += d;
            if k >= min_p {
                let mean = running / k as f64;
                s.cmnd[k - min_p] = d / (mean + f64::MIN_POSITIVE);
            }
        }
        self.candidates(s, out)
    }

    /// pYIN's trough probabilities from `s.cmnd` (librosa's `__pyin_helper`, without
    /// materialising the thresholds × troughs matrix: the set of troughs below a threshold
    /// only changes at the trough heights, so thresholds are grouped between heights).
    fn candidates(&self, s: &mut Scratch, out: &mut Vec<Candidate>) -> f32 {
        let y = &s.cmnd;
        let len = y.len();
        s.troughs.clear();
        if y[0] < y[1] {
            s.troughs.push(0);
        }
        for i in 1..len {
            let right_ok = i + 1 == len || y[i] <= y[i + 1];
            if y[i] < y[i - 1] && right_ok {
                s.troughs.push(i);
            }
        }
        if s.troughs.is_empty() {
            return 0.0;
        }
        let n_t = s.troughs.len();
        s.by_height.clear();
        s.by_height.extend(0..n_t);
        let troughs = &s.troughs;
        s.by_height
            .sort_by(|&a, &b| y[troughs[a]].total_cmp(&y[troughs[b]]).then(a.cmp(&b)));
        s.probs.clear();
        s.probs.resize(n_t, 0.0);
        let lambda = self.cfg.boltzmann_parameter;
        // Group g: the g lowest troughs are below the thresholds in [first_above(h_g-1th), ...).
        s.member.clear();
        s.member.resize(n_t, false);
        for g in 1..=n_t {
            s.member[s.by_height[g - 1]] = true;
            let from = self.prior.first_above(y[troughs[s.by_height[g - 1]]]);
            let to = if g < n_t {
                self.prior.first_above(y[troughs[s.by_height[g]]])
            } else {
                self.prior.upper.len()
            };
            if to <= from {
                continue;
            }
            let mass = self.prior.mass(from, to);
            // Members in lag order give the Boltzmann positions.
            let mut position = 0usize;
            for j in 0..n_t {
                if s.member[j] {
                    s.probs[j] += mass * boltzmann_pmf(position, lambda, g);
                    position += 1;
                }
            }
        }
        let global_min = s.by_height[0];
        let below = self.prior.first_above(y[troughs[global_min]]);
        s.probs[global_min] += self.cfg.no_trough_prob * self.prior.mass(0, below);

        let sr = f64::from(self.cfg.sample_rate_hz);
        let min_p = self.cfg.min_period() as f64;
        let mut voiced = 0.0f64;
        let frame_start = out.len();
        for (j, &i) in troughs.iter().enumerate() {
            let p = s.probs[j];
            if p <= 0.0 {
                continue;
            }
            let period = min_p + i as f64 + parabolic_shift(y, i);
            let f0 = sr / period;
            let bin = (self.bins_per_octave * (f0 / self.cfg.fmin_hz).log2()).round();
            if bin < 0.0 || bin >= self.n_bins as f64 {
                continue;
            }
            // As librosa's assignment, a later candidate in the same bin replaces an earlier.
            let bin = bin as u32;
            let same_bin = out.len() > frame_start && out.last().is_some_and(|c| c.bin == bin);
            if let (true, Some(last)) = (same_bin, out.last_mut()) {
                voiced -= f64::from(last.prob);
                last.prob = p as f32;
                last.f0_hz = f0 as f32;
            } else {
                out.push(Candidate {
                    bin,
                    prob: p as f32,
                    f0_hz: f0 as f32,
                });
            }
            voiced += p;
        }
        voiced.clamp(0.0, 1.0) as f32
    }
}

/// librosa's parabolic interpolation stencil: the optimum's offset from bin `i`, or 0 at the
/// edges and where the optimum would move by a bin or more.
fn parabolic_shift(y: &[f64], i: usize) -> f64 {
    if i == 0 || i + 1 >= y.len() {
        return 0.0;
    }
    let a = y[i + 1] + y[i - 1] - 2.0 * y[i];
    let b = (y[i + 1] - y[i - 1]) / 2.0;
    if b.abs() >= a.abs() {
        0.0
    } else {
        -b / a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sine_has_one_strong_candidate_at_its_pitch() {
        let cfg = PitchConfig::default();
        let yin = Yin::new(&cfg);
        let sr = cfg.sample_rate_hz as f32;
        let x: Vec<f32> = (0..8192)
            .map(|i| (2.0 * std::f32::consts::PI * 440.0 * i as f32 / sr).sin())
            .collect();
        let obs = yin.observe(&x);
        let mid = obs.len() / 2;
        let best = obs
            .frame(mid)
            .iter()
            .max_by(|a, b| a.prob.total_cmp(&b.prob))
            .copied()
            .unwrap();
        assert!((best.f0_hz - 440.0).abs() < 1.0, "{best:?}");
        assert!(obs.voiced_prob[mid] > 0.9);
    }

    #[test]
    fn silence_has_no_candidates() {
        let yin = Yin::new(&PitchConfig::default());
        let obs = yin.observe(&[0.0; 4096]);
        assert!(obs.candidates.is_empty());
        assert!(obs.voiced_prob.iter().all(|&v| v == 0.0));
    }
}
