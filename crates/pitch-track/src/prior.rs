//! The priors of pYIN: a beta distribution over YIN thresholds and a Boltzmann distribution
//! over troughs (Mauch & Dixon 2014, as implemented in `librosa.pyin`).

/// Probability mass of each threshold interval and its prefix sums.
#[derive(Debug, Clone)]
pub(crate) struct ThresholdPrior {
    /// `thresholds[1..]` of `linspace(0, 1, n + 1)`: the upper edge of each interval.
    pub upper: Vec<f64>,
    /// `prefix[t] = Σ_{s < t} beta_probs[s]`.
    pub prefix: Vec<f64>,
}

impl ThresholdPrior {
    /// `n` thresholds with a Beta(α, β) prior.
    pub fn new(n: usize, alpha: f64, beta: f64) -> Self {
        let thresholds: Vec<f64> = (0..=n).map(|i| i as f64 / n as f64).collect();
        let cdf: Vec<f64> = thresholds
            .iter()
            .map(|&x| regularized_incomplete_beta(alpha, beta, x))
            .collect();
        let mut prefix = Vec::with_capacity(n + 1);
        prefix.push(0.0);
        let mut acc = 0.0;
        for w in cdf.windows(2) {
            acc += w[1] - w[0];
            prefix.push(acc);
        }
        Self {
            upper: thresholds[1..].to_vec(),
            prefix,
        }
    }

    /// Number of thresholds `th` with `height >= th` (those with no trough below them when
    /// `height` is the lowest trough): the first index whose threshold exceeds `height`.
    pub fn first_above(&self, height: f64) -> usize {
        self.upper.partition_point(|&th| height >= th)
    }

    /// Beta mass of thresholds `from..to`.
    pub fn mass(&self, from: usize, to: usize) -> f64 {
        self.prefix[to] - self.prefix[from]
    }
}

/// `scipy.stats.boltzmann.pmf(k, lambda, n)`: `(1 − e^{−λ}) e^{−λk} / (1 − e^{−λn})`.
pub(crate) fn boltzmann_pmf(k: usize, lambda: f64, n: usize) -> f64 {
    if k >= n {
        return 0.0;
    }
    (1.0 - (-lambda).exp()) * (-lambda * k as f64).exp() / (1.0 - (-lambda * n as f64).exp())
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, 9 terms; relative error ~1e-15).
fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularised incomplete beta function I_x(a, b) (the Beta(a, b) CDF), by Lentz's
/// continued fraction.
pub(crate) fn regularized_incomplete_beta(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_front = ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln();
    let front = ln_front.exp();
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_continued_fraction(a, b, x) / a
    } else {
        1.0 - front * beta_continued_fraction(b, a, 1.0 - x) / b
    }
}

fn beta_continued_fraction(a: f64, b: f64, x: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < TINY {
        d = TINY;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..300 {
        let m = m as f64;
        let m2 = 2.0 * m;
        let aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < TINY { TINY } else { d };
        c = 1.0 + aa / c;
        c = if c.abs() < TINY { TINY } else { c };
        d = 1.0 / d;
        h *= d * c;
        let aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < TINY { TINY } else { d };
        c = 1.0 + aa / c;
        c = if c.abs() < TINY { TINY } else { c };
        d = 1.0 / d;
        let delta = d * c;
        h *= delta;
        if (delta - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn beta_cdf_matches_scipy() {
        // scipy.stats.beta.cdf([0.05, 0.1, 0.3], 2, 18)
        let expected = [
            0.245_292_794_929_384_5,
            0.579_735_021_168_402_6,
            0.989_578_152_973_373_1,
        ];
        for (x, e) in [0.05, 0.1, 0.3].iter().zip(expected) {
            let got = regularized_incomplete_beta(2.0, 18.0, *x);
            assert!((got - e).abs() < 1e-9, "{x}: {got} vs {e}");
        }
        let p = ThresholdPrior::new(100, 2.0, 18.0);
        assert!((p.mass(0, 100) - 1.0).abs() < 1e-12);
        assert_eq!(p.first_above(0.005), 0);
        assert_eq!(p.first_above(0.015), 1);
        assert_eq!(p.first_above(2.0), 100);
    }

    #[test]
    fn boltzmann_sums_to_one() {
        let s: f64 = (0..5).map(|k| boltzmann_pmf(k, 2.0, 5)).sum();
        assert!((s - 1.0).abs() < 1e-12);
        assert_eq!(boltzmann_pmf(5, 2.0, 5), 0.0);
    }
}
