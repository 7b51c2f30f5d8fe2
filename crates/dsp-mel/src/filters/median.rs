//! Running median with a choice of edge handling.

use serde::{Deserialize, Serialize};

use crate::error::{DspError, Result};

/// What the window sees beyond the ends of the signal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum EdgeMode {
    /// Repeat the first/last value (`scipy.ndimage.median_filter(mode='nearest')`); the seed's
    /// worked example: `[2, 3, 56, 3]` → `[2, 3, 3, 3]` with window 3.
    #[default]
    Nearest,
    /// Zeros beyond the ends (`scipy.signal.medfilt`).
    Zero,
}

/// Median of each odd-length window centred on every sample.
///
/// Runs in `O(n · window)` with a sorted window that is updated, not re-sorted, per sample.
///
/// ```
/// use dsp_mel::filters::{median_filter, EdgeMode};
/// let y = median_filter(&[2.0, 3.0, 56.0, 3.0], 3, EdgeMode::Nearest)?;
/// assert_eq!(y, vec![2.0, 3.0, 3.0, 3.0]);
/// # Ok::<(), dsp_mel::DspError>(())
/// ```
pub fn median_filter(x: &[f64], window: usize, edge: EdgeMode) -> Result<Vec<f64>> {
    if window == 0 || window.is_multiple_of(2) {
        return Err(DspError::InvalidConfig(format!(
            "median window must be odd and ≥ 1, got {window}"
        )));
    }
    if let Some(index) = x.iter().position(|v| !v.is_finite()) {
        return Err(DspError::NonFiniteInput { index });
    }
    let n = x.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let half = (window / 2) as isize;
    let at = |i: isize| -> f64 {
        if i >= 0 && (i as usize) < n {
            x[i as usize]
        } else {
            match edge {
                EdgeMode::Zero => 0.0,
                EdgeMode::Nearest => x[i.clamp(0, n as isize - 1) as usize],
            }
        }
    };
    let mut sorted: Vec<f64> = (-half..=half).map(at).collect();
    sorted.sort_by(f64::total_cmp);
    let mut out = Vec::with_capacity(n);
    out.push(sorted[window / 2]);
    for t in 1..n as isize {
        let leaving = at(t - half - 1);
        let entering = at(t + half);
        if leaving != entering {
            let pos = sorted.partition_point(|v| v.total_cmp(&leaving).is_lt());
            sorted.remove(pos);
            let ins = sorted.partition_point(|v| v.total_cmp(&entering).is_lt());
            sorted.insert(ins, entering);
        }
        out.push(sorted[window / 2]);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn naive(x: &[f64], w: usize, edge: EdgeMode) -> Vec<f64> {
        let n = x.len() as isize;
        let h = (w / 2) as isize;
        (0..n)
            .map(|t| {
                let mut v: Vec<f64> = (t - h..=t + h)
                    .map(|i| {
                        if (0..n).contains(&i) {
                            x[i as usize]
                        } else if edge == EdgeMode::Zero {
                            0.0
                        } else {
                            x[i.clamp(0, n - 1) as usize]
                        }
                    })
                    .collect();
                v.sort_by(f64::total_cmp);
                v[w / 2]
            })
            .collect()
    }

    #[test]
    fn matches_naive_on_awkward_data() {
        let x: Vec<f64> = (0..200)
            .map(|i| ((i * 37 % 23) as f64 - 11.0) * if i % 5 == 0 { 3.0 } else { 1.0 })
            .collect();
        for w in [1, 3, 5, 15, 31, 401] {
            for edge in [EdgeMode::Nearest, EdgeMode::Zero] {
                assert_eq!(median_filter(&x, w, edge).unwrap(), naive(&x, w, edge));
            }
        }
    }

    #[test]
    fn seed_example_and_zero_edges() {
        let x = [2.0, 3.0, 56.0, 3.0];
        assert_eq!(
            median_filter(&x, 3, EdgeMode::Nearest).unwrap(),
            vec![2.0, 3.0, 3.0, 3.0]
        );
        assert_eq!(
            median_filter(&x, 3, EdgeMode::Zero).unwrap(),
            vec![2.0, 3.0, 3.0, 3.0]
        );
        assert_eq!(
            median_filter(&[5.0, 5.0], 3, EdgeMode::Zero).unwrap(),
            vec![5.0, 5.0]
        );
    }

    #[test]
    fn bad_windows_and_values() {
        assert!(median_filter(&[1.0], 2, EdgeMode::Zero).is_err());
        assert!(median_filter(&[1.0], 0, EdgeMode::Zero).is_err());
        assert!(median_filter(&[1.0, f64::INFINITY], 3, EdgeMode::Zero).is_err());
        assert!(median_filter(&[], 3, EdgeMode::Zero).unwrap().is_empty());
    }
}
