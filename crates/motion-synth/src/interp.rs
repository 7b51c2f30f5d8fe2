//! Monotone cubic interpolation (Fritsch–Carlson, as SciPy's `PchipInterpolator` inside the
//! knots) with flat ends: continuous first derivative everywhere, no overshoot between
//! knots, and the end values held outside the knots.

/// A C¹ monotone cubic through knots `(x, y)`; used to turn the 2 Hz arousal curve (and
/// per-bar sway sizes) into smooth 30 fps tracks.
///
/// Interior slopes are Fritsch–Carlson's weighted harmonic means (zero at a local
/// extremum); end slopes are zero, so holding the end values outside the knots adds no kink.
///
/// ```
/// use motion_synth::interp::MonotoneCubic;
/// let c = MonotoneCubic::new(vec![0.0, 1.0, 2.0], vec![0.0, 1.0, 1.0]);
/// assert_eq!(c.eval(1.0), 1.0);
/// assert!(c.eval(1.5) <= 1.0); // no overshoot
/// assert_eq!(c.eval(-3.0), 0.0); // held outside
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MonotoneCubic {
    xs: Vec<f64>,
    ys: Vec<f64>,
    slopes: Vec<f64>,
}

impl MonotoneCubic {
    /// Builds the interpolant. `xs` must be strictly increasing and as long as `ys`
    /// (extra entries of the longer list are ignored); no knots gives the constant 0.
    pub fn new(xs: Vec<f64>, ys: Vec<f64>) -> MonotoneCubic {
        let n = xs.len().min(ys.len());
        let (mut xs, mut ys) = (xs, ys);
        xs.truncate(n);
        ys.truncate(n);
        let mut slopes = vec![0.0; n];
        for k in 1..n.saturating_sub(1) {
            let (h0, h1) = (xs[k] - xs[k - 1], xs[k + 1] - xs[k]);
            let d0 = (ys[k] - ys[k - 1]) / h0;
            let d1 = (ys[k + 1] - ys[k]) / h1;
            if d0 * d1 > 0.0 {
                let w1 = 2.0 * h1 + h0;
                let w2 = h1 + 2.0 * h0;
                slopes[k] = (w1 + w2) / (w1 / d0 + w2 / d1);
            }
        }
        MonotoneCubic { xs, ys, slopes }
    }

    /// Knots `y[i]` at `x = x0 + i · dx`.
    pub fn uniform(x0: f64, dx: f64, ys: Vec<f64>) -> MonotoneCubic {
        let xs = (0..ys.len()).map(|i| x0 + i as f64 * dx).collect();
        MonotoneCubic::new(xs, ys)
    }

    /// Number of knots.
    pub fn len(&self) -> usize {
        self.xs.len()
    }

    /// `true` with no knots.
    pub fn is_empty(&self) -> bool {
        self.xs.is_empty()
    }

    /// The value at `x` (binary search for the interval).
    pub fn eval(&self, x: f64) -> f64 {
        let k = self.xs.partition_point(|&v| v <= x);
        self.eval_in(k.saturating_sub(1), x)
    }

    /// The value at `x`, starting the interval search at `*cursor` and moving it forward;
    /// O(1) amortised when called with increasing `x` (the per-frame case).
    pub fn eval_from(&self, cursor: &mut usize, x: f64) -> f64 {
        while *cursor + 1 < self.xs.len() && self.xs[*cursor + 1] <= x {
            *cursor += 1;
        }
        self.eval_in(*cursor, x)
    }

    fn eval_in(&self, k: usize, x: f64) -> f64 {
        let n = self.xs.len();
        if n == 0 {
            return 0.0;
        }
        if x <= self.xs[0] {
            return self.ys[0];
        }
        if k + 1 >= n {
            return self.ys[n - 1];
        }
        let h = self.xs[k + 1] - self.xs[k];
        let t = ((x - self.xs[k]) / h).clamp(0.0, 1.0);
        let (t2, t3) = (t * t, t * t * t);
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + t;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        h00 * self.ys[k]
            + h10 * h * self.slopes[k]
            + h01 * self.ys[k + 1]
            + h11 * h * self.slopes[k + 1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_through_knots_and_stays_within_neighbours() {
        let ys = vec![0.0, 0.5, -0.2, -0.2, 0.9, 1.0];
        let c = MonotoneCubic::uniform(0.0, 0.5, ys.clone());
        for (i, &y) in ys.iter().enumerate() {
            assert!((c.eval(i as f64 * 0.5) - y).abs() < 1e-12);
        }
        for k in 0..ys.len() - 1 {
            let (lo, hi) = (ys[k].min(ys[k + 1]), ys[k].max(ys[k + 1]));
            for s in 0..=20 {
                let v = c.eval((k as f64 + s as f64 / 20.0) * 0.5);
                assert!(
                    v >= lo - 1e-12 && v <= hi + 1e-12,
                    "overshoot at {k},{s}: {v}"
                );
            }
        }
    }

    #[test]
    fn derivative_is_continuous() {
        let c = MonotoneCubic::uniform(0.0, 0.5, vec![0.0, 0.3, 0.4, -0.6, 0.2, 0.2, 0.8]);
        let slope = |x: f64| (c.eval(x + 1e-6) - c.eval(x - 1e-6)) / 2e-6;
        for k in 0..8 {
            let x = k as f64 * 0.5;
            let left = (c.eval(x) - c.eval(x - 1e-5)) / 1e-5;
            let right = (c.eval(x + 1e-5) - c.eval(x)) / 1e-5;
            assert!(
                (left - right).abs() < 1e-3,
                "kink at {x}: {left} vs {right}"
            );
            assert!(slope(x).is_finite());
        }
    }

    #[test]
    fn cursor_matches_binary_search_and_degenerate_inputs_work() {
        let c = MonotoneCubic::uniform(0.0, 0.5, vec![0.1, 0.7, 0.2]);
        let mut cursor = 0;
        for i in 0..60 {
            let x = i as f64 / 30.0 - 0.2;
            assert_eq!(c.eval_from(&mut cursor, x), c.eval(x));
        }
        assert_eq!(MonotoneCubic::new(vec![], vec![]).eval(1.0), 0.0);
        assert_eq!(MonotoneCubic::uniform(0.0, 1.0, vec![0.4]).eval(9.0), 0.4);
    }
}
