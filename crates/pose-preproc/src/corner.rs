//! Where a bow change lies inside a run of detections: the knot of a least-squares hinge.
//!
//! Near a change the wrist's coordinate along the bow is two straight-ish strokes meeting at
//! a corner. Over `±half` frames around a candidate knot `c` the track is fitted with a
//! continuous broken line `a + b₁·min(t − c, 0) + b₂·max(t − c, 0)`; the change is the `c`
//! with the smallest squared residual. Every sample of the window counts, so pixel jitter
//! moves the knot far less than it moves an extremum or a difference of three filtered
//! samples, and a change between two strokes of different speeds is not pulled towards the
//! slower one.

/// Prefix sums of `1, t, t², y, t·y, y²` (t relative to the track's start) for O(1)
/// least-squares sums over any window.
pub(crate) struct HingeSums {
    prefix: Vec<[f64; 6]>,
}

impl HingeSums {
    /// The sums of `track`.
    pub(crate) fn new(track: &[f64]) -> Self {
        let mut prefix = Vec::with_capacity(track.len() + 1);
        let mut acc = [0.0f64; 6];
        prefix.push(acc);
        for (t, &y) in track.iter().enumerate() {
            let t = t as f64;
            for (a, v) in acc.iter_mut().zip([1.0, t, t * t, y, t * y, y * y]) {
                *a += v;
            }
            prefix.push(acc);
        }
        HingeSums { prefix }
    }

    /// Sums over frames `a..b` of `1, u, u², y, u·y, y²` with `u = t − c`.
    fn sums(&self, a: usize, b: usize, c: f64) -> [f64; 6] {
        let (p, q) = (&self.prefix[b], &self.prefix[a]);
        let s: [f64; 6] = std::array::from_fn(|k| p[k] - q[k]);
        // Shift t → t − c.
        [
            s[0],
            s[1] - c * s[0],
            s[2] - 2.0 * c * s[1] + c * c * s[0],
            s[3],
            s[4] - c * s[3],
            s[5],
        ]
    }

    /// Squared residual of the best hinge with its knot at frame `c`, fitted on frames
    /// `lo..hi`; `None` when a side of the knot has fewer than two frames.
    pub(crate) fn residual(&self, (lo, hi): (usize, usize), c: usize) -> Option<f64> {
        let hi = hi.min(self.prefix.len() - 1);
        if c < lo + 2 || c + 3 > hi {
            return None;
        }
        let cf = c as f64;
        // Left side: frames lo..c (u < 0), right side: c+1..hi (u > 0); the knot frame has
        // u = 0 and only counts in the intercept.
        let l = self.sums(lo, c, cf);
        let r = self.sums(c + 1, hi, cf);
        let k = self.sums(c, c + 1, cf);
        let n0 = l[0] + r[0] + k[0];
        let sy = l[3] + r[3] + k[3];
        let syy = l[5] + r[5] + k[5];
        // Normal equations for (a, b1, b2) with regressors 1, u₋, u₊.
        let m = [[n0, l[1], r[1]], [l[1], l[2], 0.0], [r[1], 0.0, r[2]]];
        let rhs = [sy, l[4], r[4]];
        let beta = solve3(m, rhs)?;
        let fit: f64 = beta.iter().zip(rhs).map(|(b, v)| b * v).sum();
        Some((syy - fit).max(0.0))
    }
}

/// Solves the symmetric 3×3 system `m · x = rhs` (Cramer's rule); `None` when singular.
fn solve3(m: [[f64; 3]; 3], rhs: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(m);
    if !d.is_finite() || d.abs() < 1e-12 {
        return None;
    }
    let mut x = [0.0; 3];
    for (col, slot) in x.iter_mut().enumerate() {
        let mut mc = m;
        for row in 0..3 {
            mc[row][col] = rhs[row];
        }
        *slot = det(mc) / d;
    }
    Some(x)
}

/// The knot frame in `candidates` (inclusive) whose hinge fits `sums`' track best over the
/// fixed `window` of frames `lo..hi` (the same frames for every candidate, so residuals
/// compare); `fallback` when no knot can be fitted.
pub(crate) fn best_knot(
    sums: &HingeSums,
    window: (usize, usize),
    candidates: (usize, usize),
    fallback: usize,
) -> usize {
    let mut best = (f64::INFINITY, fallback);
    for c in candidates.0..=candidates.1 {
        if let Some(r) = sums.residual(window, c) {
            if r < best.0 {
                best = (r, c);
            }
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_an_asymmetric_corner_exactly() {
        // Slope 3 up to frame 40, then −1: the corner is at 40.
        let y: Vec<f64> = (0..80)
            .map(|t| {
                let t = t as f64;
                if t <= 40.0 {
                    3.0 * t
                } else {
                    120.0 - (t - 40.0)
                }
            })
            .collect();
        let sums = HingeSums::new(&y);
        assert!(sums.residual((30, 51), 40).unwrap() < 1e-6);
        assert!(sums.residual((30, 51), 38).unwrap() > 1.0);
        assert_eq!(best_knot(&sums, (25, 56), (33, 47), 0), 40);
    }

    #[test]
    fn too_few_frames_give_no_fit() {
        let sums = HingeSums::new(&[0.0, 1.0, 2.0]);
        assert!(sums.residual((0, 3), 1).is_none());
        assert_eq!(best_knot(&sums, (0, 3), (0, 2), 7), 7);
    }
}
