//! Direct-form II transposed filtering and zero-phase forward–backward filtering, equal to
//! `scipy.signal.lfilter` / `lfilter_zi` / `filtfilt` (pad type `odd`).

use crate::error::{DspError, Result};
use crate::filters::TransferFunction;

/// Normalises `(b, a)` so `a[0] = 1` and pads both to the same length.
fn normalised(b: &[f64], a: &[f64]) -> Result<(Vec<f64>, Vec<f64>)> {
    let a0 = *a
        .first()
        .ok_or_else(|| DspError::InvalidConfig("denominator `a` is empty".into()))?;
    if b.is_empty() {
        return Err(DspError::InvalidConfig("numerator `b` is empty".into()));
    }
    if a0 == 0.0 || !a0.is_finite() {
        return Err(DspError::InvalidConfig(
            "a[0] must be finite and non-zero".into(),
        ));
    }
    if b.iter().chain(a).any(|c| !c.is_finite()) {
        return Err(DspError::InvalidConfig(
            "filter coefficients must be finite".into(),
        ));
    }
    let n = a.len().max(b.len());
    let mut bn = vec![0.0; n];
    let mut an = vec![0.0; n];
    for (d, s) in bn.iter_mut().zip(b) {
        *d = s / a0;
    }
    for (d, s) in an.iter_mut().zip(a) {
        *d = s / a0;
    }
    Ok((bn, an))
}

fn check_finite(x: &[f64]) -> Result<()> {
    match x.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(DspError::NonFiniteInput { index }),
        None => Ok(()),
    }
}

/// Filters `x` with `(b, a)` in direct form II transposed, starting from state `zi`
/// (`None` = rest). Returns the output; `zi` is left holding the final state.
pub fn lfilter(b: &[f64], a: &[f64], x: &[f64], zi: Option<&mut [f64]>) -> Result<Vec<f64>> {
    let (b, a) = normalised(b, a)?;
    check_finite(x)?;
    let mut local;
    let z: &mut [f64] = match zi {
        Some(z) if z.len() == b.len() - 1 => z,
        Some(z) => {
            return Err(DspError::InvalidConfig(format!(
                "initial state has {} values, the filter needs {}",
                z.len(),
                b.len() - 1
            )))
        }
        None => {
            local = vec![0.0; b.len() - 1];
            &mut local
        }
    };
    let mut y = Vec::with_capacity(x.len());
    run_df2t(&b, &a, x.iter().copied(), z, &mut y);
    Ok(y)
}

fn run_df2t(b: &[f64], a: &[f64], x: impl Iterator<Item = f64>, z: &mut [f64], y: &mut Vec<f64>) {
    let order = z.len();
    for xn in x {
        let yn = b[0] * xn + z.first().copied().unwrap_or(0.0);
        for i in 0..order {
            let next = if i + 1 < order { z[i + 1] } else { 0.0 };
            z[i] = b[i + 1] * xn + next - a[i + 1] * yn;
        }
        y.push(yn);
    }
}

/// Steady-state initial conditions for a step input of height 1 (`scipy.signal.lfilter_zi`).
pub fn lfilter_zi(b: &[f64], a: &[f64]) -> Result<Vec<f64>> {
    let (b, a) = normalised(b, a)?;
    let m = b.len() - 1;
    if m == 0 {
        return Ok(Vec::new());
    }
    // (I − companion(a)ᵀ) · zi = b[1:] − a[1:]·b[0]
    let mut mat = vec![vec![0.0; m]; m];
    for (i, row) in mat.iter_mut().enumerate() {
        row[i] = 1.0;
        row[0] += a[i + 1];
        if i + 1 < m {
            row[i + 1] -= 1.0;
        }
    }
    let rhs: Vec<f64> = (0..m).map(|i| b[i + 1] - a[i + 1] * b[0]).collect();
    solve(mat, rhs).ok_or_else(|| {
        DspError::InvalidConfig("filter has no steady state (unstable or singular)".into())
    })
}

/// Gaussian elimination with partial pivoting.
fn solve(mut m: Vec<Vec<f64>>, mut r: Vec<f64>) -> Option<Vec<f64>> {
    let n = r.len();
    for col in 0..n {
        let piv = (col..n).max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))?;
        if m[piv][col].abs() < 1e-300 {
            return None;
        }
        m.swap(col, piv);
        r.swap(col, piv);
        let (upper, lower) = m.split_at_mut(col + 1);
        let pivot_row = &upper[col];
        let pivot_rhs = r[col];
        for (offset, row) in lower.iter_mut().enumerate() {
            let f = row[col] / pivot_row[col];
            if f != 0.0 {
                for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                    *x -= f * p;
                }
                r[col + 1 + offset] -= f * pivot_rhs;
            }
        }
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|k| m[i][k] * x[k]).sum();
        x[i] = (r[i] - s) / m[i][i];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Zero-phase filtering exactly as `scipy.signal.filtfilt(b, a, x)` with its defaults:
/// odd extension of `3 · max(len(a), len(b))` samples at each end, steady-state initial
/// conditions, forward then backward pass. `x` must be longer than the padding.
///
/// ```
/// use dsp_mel::filters::{filtfilt, Butterworth};
/// let tf = Butterworth::lowpass(4, 5.0, 30.0)?.transfer_function();
/// let x: Vec<f64> = (0..100).map(|i| (i as f64 * 0.3).sin()).collect();
/// let y = filtfilt(&tf.b, &tf.a, &x)?;
/// assert_eq!(y.len(), x.len());
/// # Ok::<(), dsp_mel::DspError>(())
/// ```
pub fn filtfilt(b: &[f64], a: &[f64], x: &[f64]) -> Result<Vec<f64>> {
    filtfilt_padlen(b, a, x, 3 * a.len().max(b.len()))
}

/// [`filtfilt`] for a [`TransferFunction`].
pub fn filtfilt_tf(tf: &TransferFunction, x: &[f64]) -> Result<Vec<f64>> {
    filtfilt(&tf.b, &tf.a, x)
}

/// [`filtfilt`] with an explicit pad length (`scipy`'s `padlen=`).
pub fn filtfilt_padlen(b: &[f64], a: &[f64], x: &[f64], padlen: usize) -> Result<Vec<f64>> {
    check_finite(x)?;
    if x.len() <= padlen {
        return Err(DspError::TooShort {
            len: x.len(),
            needed: padlen,
        });
    }
    let (bn, an) = normalised(b, a)?;
    let zi = lfilter_zi(&bn, &an)?;
    let n = x.len();
    let (first, last) = (x[0], x[n - 1]);
    // Odd extension: 2·x[0] − x[padlen..0], x, 2·x[-1] − x[-2..-padlen-2].
    let mut ext = Vec::with_capacity(n + 2 * padlen);
    ext.extend((1..=padlen).rev().map(|i| 2.0 * first - x[i]));
    ext.extend_from_slice(x);
    ext.extend((1..=padlen).map(|i| 2.0 * last - x[n - 1 - i]));

    let mut z: Vec<f64> = zi.iter().map(|v| v * ext[0]).collect();
    let mut fwd = Vec::with_capacity(ext.len());
    run_df2t(&bn, &an, ext.iter().copied(), &mut z, &mut fwd);
    let y0 = fwd.last().copied().unwrap_or(0.0);
    let mut z: Vec<f64> = zi.iter().map(|v| v * y0).collect();
    let mut back = Vec::with_capacity(ext.len());
    run_df2t(&bn, &an, fwd.iter().rev().copied(), &mut z, &mut back);
    back.reverse();
    Ok(back[padlen..padlen + n].to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_passes_unchanged() {
        let tf = crate::filters::Butterworth::lowpass(4, 5.0, 30.0)
            .unwrap()
            .transfer_function();
        let y = filtfilt(&tf.b, &tf.a, &[3.0; 40]).unwrap();
        assert!(y.iter().all(|v| (v - 3.0).abs() < 1e-9));
    }

    #[test]
    fn too_short_and_nan_are_errors() {
        let tf = crate::filters::Butterworth::lowpass(4, 5.0, 30.0)
            .unwrap()
            .transfer_function();
        assert!(matches!(
            filtfilt(&tf.b, &tf.a, &[1.0; 15]),
            Err(DspError::TooShort {
                len: 15,
                needed: 15
            })
        ));
        let mut x = vec![0.0; 40];
        x[7] = f64::NAN;
        assert!(matches!(
            filtfilt(&tf.b, &tf.a, &x),
            Err(DspError::NonFiniteInput { index: 7 })
        ));
        assert!(lfilter(&[1.0], &[0.0], &[1.0], None).is_err());
    }

    #[test]
    fn lfilter_moving_average() {
        let y = lfilter(&[0.5, 0.5], &[1.0], &[2.0, 4.0, 6.0], None).unwrap();
        assert_eq!(y, vec![1.0, 3.0, 5.0]);
    }
}
