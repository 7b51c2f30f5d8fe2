//! Butterworth low-pass design, equal to `scipy.signal.butter(N, cutoff, fs=fs)`.

use realfft::num_complex::Complex64;
use serde::{Deserialize, Serialize};

use crate::error::{DspError, Result};

/// A digital filter in transfer-function form: `b` (numerator) and `a` (denominator, `a[0] = 1`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TransferFunction {
    /// Numerator coefficients.
    pub b: Vec<f64>,
    /// Denominator coefficients.
    pub a: Vec<f64>,
}

/// One second-order section `[b0, b1, b2, a0, a1, a2]` (scipy's `sos` row layout).
pub type SecondOrderSection = [f64; 6];

/// A Butterworth low-pass design, kept as poles, zeros and gain so both output forms are
/// exact conversions of the same design.
///
/// ```
/// let lp = dsp_mel::filters::Butterworth::lowpass(4, 5.0, 30.0)?;
/// let tf = lp.transfer_function();
/// assert_eq!((tf.b.len(), tf.a.len()), (5, 5));
/// assert_eq!(lp.second_order_sections().len(), 2);
/// # Ok::<(), dsp_mel::DspError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Butterworth {
    zeros: Vec<Complex64>,
    poles: Vec<Complex64>,
    gain: f64,
}

impl Butterworth {
    /// Designs an order-`order` low-pass with its −3 dB point at `cutoff_hz` for sample rate
    /// `fs_hz` (bilinear transform with pre-warping, as scipy).
    pub fn lowpass(order: usize, cutoff_hz: f64, fs_hz: f64) -> Result<Self> {
        if order == 0 || order > 24 {
            return Err(DspError::InvalidConfig(format!(
                "Butterworth order must be 1..=24, got {order}"
            )));
        }
        if !(fs_hz.is_finite() && fs_hz > 0.0) {
            return Err(DspError::InvalidConfig(format!(
                "sample rate must be > 0, got {fs_hz}"
            )));
        }
        let wn = 2.0 * cutoff_hz / fs_hz;
        if !(wn.is_finite() && wn > 0.0 && wn < 1.0) {
            return Err(DspError::InvalidConfig(format!(
                "cutoff must be between 0 and Nyquist ({} Hz), got {cutoff_hz}",
                fs_hz / 2.0
            )));
        }
        let n = order as f64;
        // Analog prototype poles: -exp(iπm / 2N), m = -N+1, -N+3, …, N-1.
        let proto: Vec<Complex64> = (0..order)
            .map(|i| {
                let m = -(n - 1.0) + 2.0 * i as f64;
                -Complex64::from_polar(1.0, std::f64::consts::PI * m / (2.0 * n))
            })
            .collect();
        // Pre-warp (scipy works at fs = 2 after normalising the cutoff).
        let fs = 2.0;
        let warped = 2.0 * fs * (std::f64::consts::PI * wn / fs).tan();
        let poles_s: Vec<Complex64> = proto.iter().map(|p| p * warped).collect();
        let gain_s = warped.powi(order as i32);
        // Bilinear transform.
        let fs2 = Complex64::new(2.0 * fs, 0.0);
        let poles: Vec<Complex64> = poles_s.iter().map(|p| (fs2 + p) / (fs2 - p)).collect();
        let zeros = vec![Complex64::new(-1.0, 0.0); order];
        let denom: Complex64 = poles_s.iter().map(|p| fs2 - p).product();
        let gain = gain_s * (Complex64::new(1.0, 0.0) / denom).re;
        Ok(Self { zeros, poles, gain })
    }

    /// Numerator and denominator polynomials (scipy `output='ba'`).
    pub fn transfer_function(&self) -> TransferFunction {
        let b = poly(&self.zeros).iter().map(|c| c.re * self.gain).collect();
        let a = poly(&self.poles).iter().map(|c| c.re).collect();
        TransferFunction { b, a }
    }

    /// Second-order sections (scipy `output='sos'`, `pairing='nearest'`): poles closest to the
    /// unit circle in the last section, the gain in the first.
    pub fn second_order_sections(&self) -> Vec<SecondOrderSection> {
        let mut z: Vec<f64> = self.zeros.iter().map(|c| c.re).collect();
        let mut p = self.poles.clone();
        if p.len() % 2 == 1 {
            p.push(Complex64::new(0.0, 0.0));
            z.push(0.0);
        }
        let n_sections = p.len() / 2;
        // One representative per conjugate pair (positive imaginary part), then the reals,
        // in scipy's `_cplxreal` order.
        let tol = 100.0 * f64::EPSILON;
        let is_real = |c: &Complex64| c.im.abs() <= tol * c.norm();
        let mut pairs: Vec<Complex64> = p
            .iter()
            .filter(|c| !is_real(c) && c.im > 0.0)
            .copied()
            .collect();
        pairs.sort_by(|x, y| {
            x.re.total_cmp(&y.re)
                .then(x.im.abs().total_cmp(&y.im.abs()))
        });
        let mut reals: Vec<Complex64> = p
            .iter()
            .filter(|c| is_real(c))
            .map(|c| Complex64::new(c.re, 0.0))
            .collect();
        reals.sort_by(|x, y| x.re.total_cmp(&y.re));
        let mut p: Vec<Complex64> = pairs.into_iter().chain(reals).collect();
        z.sort_by(f64::total_cmp);

        let worst = |v: &[Complex64]| -> Option<usize> {
            v.iter()
                .enumerate()
                .min_by(|(_, x), (_, y)| (1.0 - x.norm()).abs().total_cmp(&(1.0 - y.norm()).abs()))
                .map(|(i, _)| i)
        };
        let nearest_zero = |z: &[f64], to: Complex64| -> Option<usize> {
            z.iter()
                .enumerate()
                .min_by(|(_, x), (_, y)| {
                    (Complex64::new(**x, 0.0) - to)
                        .norm()
                        .total_cmp(&(Complex64::new(**y, 0.0) - to).norm())
                })
                .map(|(i, _)| i)
        };
        let mut sos = vec![[0.0; 6]; n_sections];
        for si in (0..n_sections).rev() {
            let Some(i1) = worst(&p) else { break };
            let p1 = p.remove(i1);
            let p1_real = is_real(&p1);
            let remaining_reals: Vec<usize> = (0..p.len()).filter(|&i| is_real(&p[i])).collect();
            let take_zero = |z: &mut Vec<f64>| nearest_zero(z, p1).map(|i| z.remove(i));
            if p1_real && remaining_reals.is_empty() {
                let z1 = take_zero(&mut z).unwrap_or(0.0);
                sos[si] = single_section(&[z1, 0.0], &[p1, Complex64::new(0.0, 0.0)]);
                continue;
            }
            let p2 = if p1_real {
                let sub: Vec<Complex64> = remaining_reals.iter().map(|&i| p[i]).collect();
                let j = worst(&sub).map_or(remaining_reals[0], |j| remaining_reals[j]);
                p.remove(j)
            } else {
                p1.conj()
            };
            let zs: Vec<f64> = [take_zero(&mut z), take_zero(&mut z)]
                .into_iter()
                .flatten()
                .collect();
            sos[si] = single_section(&zs, &[p1, p2]);
        }
        if let Some(first) = sos.first_mut() {
            for c in &mut first[..3] {
                *c *= self.gain;
            }
        }
        sos
    }
}

/// One section from up to two (real) zeros and two poles, right-aligned like scipy.
fn single_section(zeros: &[f64], poles: &[Complex64]) -> SecondOrderSection {
    let zc: Vec<Complex64> = zeros.iter().map(|&x| Complex64::new(x, 0.0)).collect();
    let b = poly(&zc);
    let a = poly(poles);
    let mut s = [0.0; 6];
    for (i, c) in b.iter().enumerate() {
        s[3 - b.len() + i] = c.re;
    }
    for (i, c) in a.iter().enumerate() {
        s[6 - a.len() + i] = c.re;
    }
    s
}

/// Coefficients of `∏ (x − rᵢ)`, highest power first (numpy's `poly`).
fn poly(roots: &[Complex64]) -> Vec<Complex64> {
    let mut c = vec![Complex64::new(1.0, 0.0)];
    for r in roots {
        let mut next = vec![Complex64::new(0.0, 0.0); c.len() + 1];
        for (i, ci) in c.iter().enumerate() {
            next[i] += ci;
            next[i + 1] -= ci * r;
        }
        c = next;
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unity_gain_at_dc() {
        for order in 1..=8 {
            let tf = Butterworth::lowpass(order, 5.0, 30.0)
                .unwrap()
                .transfer_function();
            let dc = tf.b.iter().sum::<f64>() / tf.a.iter().sum::<f64>();
            assert!((dc - 1.0).abs() < 1e-9, "order {order}: {dc}");
        }
    }

    #[test]
    fn rejects_bad_designs() {
        assert!(Butterworth::lowpass(0, 5.0, 30.0).is_err());
        assert!(Butterworth::lowpass(4, 15.0, 30.0).is_err());
        assert!(Butterworth::lowpass(4, -1.0, 30.0).is_err());
        assert!(Butterworth::lowpass(4, 5.0, f64::NAN).is_err());
    }
}
