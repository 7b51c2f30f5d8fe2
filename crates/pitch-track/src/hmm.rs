//! pYIN's hidden Markov model: states are pitch bins × {voiced, unvoiced}; a triangular
//! local transition within a maximum pitch jump per frame, and a small probability of
//! switching voicing (librosa's `transition_local(..., window="triangle")` ⊗
//! `transition_loop(2, 1 − switch_prob)`), decoded by Viterbi.
//!
//! The decoder never builds the dense `2n × 2n` matrix: every state has at most
//! `2 · (width + 1)` predecessors, so one frame costs O(n · width) and the transitions are
//! stored by diagonal so the inner loop runs over contiguous memory.

use crate::config::PitchConfig;
use crate::yin::Observations;

/// `ln` of a probability with librosa's `+ tiny` guard, so zero becomes ≈ −708.
fn ln_guarded(p: f64) -> f32 {
    (p + f64::MIN_POSITIVE).ln() as f32
}

/// The banded transition model and the decoder.
#[derive(Debug, Clone)]
pub(crate) struct Hmm {
    n_bins: usize,
    /// Half width of the band: predecessors of bin `j` are `j − half ..= j + half`.
    half: usize,
    /// `diag[(d + half) * n + j] = ln T(j − d → j)` for `d` in `−half..=half`.
    diag: Vec<f32>,
    ln_stay: f32,
    ln_switch: f32,
    /// The unvoiced probability mass is spread over this many states: the number of
    /// 10-cent bins (librosa's default resolution), whatever the resolution, so the voicing
    /// decision does not change with the bin width.
    unvoiced_spread: f64,
}

impl Hmm {
    pub fn new(cfg: &PitchConfig) -> Self {
        let n = cfg.n_pitch_bins();
        let per_frame =
            cfg.max_transition_rate * 12.0 * cfg.hop_length as f64 / f64::from(cfg.sample_rate_hz);
        let width = round_half_even(per_frame) as usize * cfg.bins_per_semitone() + 1;
        let half = width / 2 + 1;
        let mut diag = vec![ln_guarded(0.0); (2 * half + 1) * n];
        let mut row = vec![0.0f64; n];
        for i in 0..n {
            transition_row(n, width, i, &mut row);
            for (j, &p) in row.iter().enumerate() {
                let d = j as isize - i as isize;
                if d.unsigned_abs() <= half {
                    diag[(d + half as isize) as usize * n + j] = ln_guarded(p);
                }
            }
        }
        Self {
            n_bins: n,
            half,
            diag,
            ln_stay: ln_guarded(1.0 - cfg.switch_prob),
            ln_switch: ln_guarded(cfg.switch_prob),
            unvoiced_spread: (120.0 * (cfg.fmax_hz / cfg.fmin_hz).log2()).floor() + 1.0,
        }
    }

    /// The most likely state of every frame: `Some(bin)` when voiced, `None` when unvoiced.
    pub fn decode(&self, obs: &Observations) -> Vec<Option<usize>> {
        let n = self.n_bins;
        let frames = obs.len();
        if frames == 0 {
            return Vec::new();
        }
        let mut back = vec![0u16; frames * 2 * n];
        let mut score = vec![0.0f32; 2 * n];
        let mut next = vec![0.0f32; 2 * n];
        let mut emit = vec![0.0f32; 2 * n];
        let mut to_voiced = vec![0.0f32; n];
        let mut to_unvoiced = vec![0.0f32; n];
        let mut from_unvoiced_v = vec![false; n];
        let mut from_unvoiced_u = vec![false; n];
        let mut best_d_v = vec![0u32; n];
        let mut best_d_u = vec![0u32; n];

        self.emissions(obs, 0, &mut emit);
        let ln_init = ln_guarded(1.0 / (2 * n) as f64);
        for (s, e) in score.iter_mut().zip(&emit) {
            *s = ln_init + e;
        }
        for t in 1..frames {
            self.emissions(obs, t, &mut emit);
            let (voiced, unvoiced) = score.split_at(n);
            for i in 0..n {
                let (vv, uv) = (voiced[i] + self.ln_stay, unvoiced[i] + self.ln_switch);
                from_unvoiced_v[i] = uv > vv;
                to_voiced[i] = vv.max(uv);
                let (vu, uu) = (voiced[i] + self.ln_switch, unvoiced[i] + self.ln_stay);
                from_unvoiced_u[i] = uu > vu;
                to_unvoiced[i] = vu.max(uu);
            }
            let (next_v, next_u) = next.split_at_mut(n);
            self.band_max(&to_voiced, next_v, &mut best_d_v);
            self.band_max(&to_unvoiced, next_u, &mut best_d_u);
            let row = &mut back[t * 2 * n..(t + 1) * 2 * n];
            let mut peak = f32::NEG_INFINITY;
            for j in 0..n {
                let src_v = j + self.half - best_d_v[j] as usize;
                let src_u = j + self.half - best_d_u[j] as usize;
                row[j] = (src_v + if from_unvoiced_v[src_v] { n } else { 0 }) as u16;
                row[n + j] = (src_u + if from_unvoiced_u[src_u] { n } else { 0 }) as u16;
                next_v[j] += emit[j];
                next_u[j] += emit[n + j];
                peak = peak.max(next_v[j]).max(next_u[j]);
            }
            // Keep scores near zero so f32 keeps its precision over long files.
            for (s, x) in score.iter_mut().zip(&next) {
                *s = x - peak;
            }
        }
        let mut state = (0..2 * n)
            .max_by(|&a, &b| score[a].total_cmp(&score[b]).then(b.cmp(&a)))
            .unwrap_or(n);
        let mut path = vec![None; frames];
        for t in (0..frames).rev() {
            path[t] = (state < n).then_some(state);
            if t > 0 {
                state = usize::from(back[t * 2 * n + state]);
            }
        }
        path
    }

    /// `out[j] = max_d (from[j − d] + ln T(j − d → j))`, `best[j]` = the winning `d + half`
    /// (the first on ties). One pass per diagonal over contiguous slices, written as
    /// branch-free selects so that it vectorises.
    fn band_max(&self, from: &[f32], out: &mut [f32], best: &mut [u32]) {
        let n = self.n_bins;
        out.fill(f32::NEG_INFINITY);
        best.fill(self.half as u32);
        for k in 0..=2 * self.half {
            // Diagonal d = k − half: bins lo..hi take from bins lo − d..hi − d.
            let (lo, hi, src_lo) = if k >= self.half {
                let d = k - self.half;
                (d, n, 0)
            } else {
                let d = self.half - k;
                (0, n - d, d)
            };
            if lo >= hi {
                continue;
            }
            let src = &from[src_lo..src_lo + (hi - lo)];
            let diag = &self.diag[k * n + lo..k * n + hi];
            let kk = k as u32;
            for (((o, b), &f), &t) in out[lo..hi]
                .iter_mut()
                .zip(&mut best[lo..hi])
                .zip(src)
                .zip(diag)
            {
                let cand = f + t;
                let better = cand > *o;
                *o = if better { cand } else { *o };
                *b = if better { kk } else { *b };
            }
        }
    }

    fn emissions(&self, obs: &Observations, t: usize, emit: &mut [f32]) {
        let n = self.n_bins;
        let floor = ln_guarded(0.0);
        emit[..n].fill(floor);
        for c in obs.frame(t) {
            emit[c.bin as usize] = ln_guarded(f64::from(c.prob));
        }
        let unvoiced = ln_guarded((1.0 - f64::from(obs.voiced_prob[t])) / self.unvoiced_spread);
        emit[n..].fill(unvoiced);
    }
}

/// Python's `round`: halves go to the even neighbour.
fn round_half_even(x: f64) -> f64 {
    let r = x.round();
    if (x - x.trunc()).abs() == 0.5 && r % 2.0 != 0.0 {
        r - x.signum()
    } else {
        r
    }
}

/// Row `i` of librosa's `transition_local(n, width, window="triangle", wrap=False)`,
/// row-normalised.
fn transition_row(n: usize, width: usize, i: usize, row: &mut [f64]) {
    // scipy.signal.windows.triang(width, sym=True)
    let half = width.div_ceil(2);
    let mut window = Vec::with_capacity(width);
    for k in 1..=half {
        window.push(if width.is_multiple_of(2) {
            (2 * k - 1) as f64 / width as f64
        } else {
            2.0 * k as f64 / (width + 1) as f64
        });
    }
    let mirrored: Vec<f64> = if width.is_multiple_of(2) {
        window.iter().rev().copied().collect()
    } else {
        window.iter().rev().skip(1).copied().collect()
    };
    window.extend(mirrored);
    // pad_center, then np.roll by n/2 + i + 1, then knock out the off-band entries.
    row.fill(0.0);
    let lpad = (n.saturating_sub(width)) / 2;
    let shift = n / 2 + i + 1;
    for (k, &w) in window.iter().enumerate().take(n) {
        row[(lpad + k + shift) % n] = w;
    }
    let upper = (i + width / 2 + 1).min(n);
    row[upper..].fill(0.0);
    let lower = i.saturating_sub(width / 2);
    row[..lower].fill(0.0);
    let sum: f64 = row.iter().sum();
    if sum > 0.0 {
        row.iter_mut().for_each(|p| *p /= sum);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transition_rows_are_centred_triangles() {
        let mut row = vec![0.0; 50];
        transition_row(50, 5, 20, &mut row);
        // triang(5) = [1/3, 2/3, 1, 2/3, 1/3], centred on 20, normalised by 3.
        assert!((row[20] - 1.0 / 3.0).abs() < 1e-12);
        assert!((row[18] - 1.0 / 9.0).abs() < 1e-12);
        assert_eq!(row[17], 0.0);
        assert_eq!(row[23], 0.0);
        transition_row(50, 5, 0, &mut row);
        assert!((row.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        assert_eq!(row[49], 0.0);
        assert_eq!(round_half_even(2.5), 2.0);
        assert_eq!(round_half_even(5.004), 5.0);
    }
}
