//! RBJ-cookbook biquads (peaking EQ, band-pass) in direct form I, f64.

/// One second-order IIR section with its state.
#[derive(Debug, Clone, Copy)]
pub struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
    x: [f64; 2],
    y: [f64; 2],
}

impl Biquad {
    fn from_coeffs(b0: f64, b1: f64, b2: f64, a0: f64, a1: f64, a2: f64) -> Self {
        Self {
            b: [b0 / a0, b1 / a0, b2 / a0],
            a: [a1 / a0, a2 / a0],
            x: [0.0; 2],
            y: [0.0; 2],
        }
    }

    /// Peaking EQ at `freq_hz` with `gain_db` and quality `q` (frequencies at or above
    /// Nyquist are clamped just below it).
    pub fn peaking(sample_rate_hz: f64, freq_hz: f64, gain_db: f64, q: f64) -> Self {
        let f = freq_hz.min(0.45 * sample_rate_hz);
        let a = 10f64.powf(gain_db / 40.0);
        let w0 = 2.0 * std::f64::consts::PI * f / sample_rate_hz;
        let alpha = w0.sin() / (2.0 * q);
        let c = w0.cos();
        Self::from_coeffs(
            1.0 + alpha * a,
            -2.0 * c,
            1.0 - alpha * a,
            1.0 + alpha / a,
            -2.0 * c,
            1.0 - alpha / a,
        )
    }

    /// Band-pass with 0 dB peak gain at `freq_hz`.
    pub fn bandpass(sample_rate_hz: f64, freq_hz: f64, q: f64) -> Self {
        let f = freq_hz.min(0.45 * sample_rate_hz);
        let w0 = 2.0 * std::f64::consts::PI * f / sample_rate_hz;
        let alpha = w0.sin() / (2.0 * q);
        let c = w0.cos();
        Self::from_coeffs(alpha, 0.0, -alpha, 1.0 + alpha, -2.0 * c, 1.0 - alpha)
    }

    /// Filters one sample.
    #[inline]
    pub fn process(&mut self, x: f64) -> f64 {
        let y = self.b[0] * x + self.b[1] * self.x[0] + self.b[2] * self.x[1]
            - self.a[0] * self.y[0]
            - self.a[1] * self.y[1];
        self.x = [x, self.x[0]];
        self.y = [y, self.y[0]];
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gain_at(mut f: Biquad, sr: f64, hz: f64) -> f64 {
        let n = (sr * 0.5) as usize;
        let mut peak = 0.0f64;
        for i in 0..n {
            let y = f.process((2.0 * std::f64::consts::PI * hz * i as f64 / sr).sin());
            if i > n / 2 {
                peak = peak.max(y.abs());
            }
        }
        peak
    }

    #[test]
    fn peaking_boosts_its_centre_only() {
        let sr = 22_050.0;
        let g = gain_at(Biquad::peaking(sr, 1000.0, 6.0, 2.0), sr, 1000.0);
        assert!((g - 10f64.powf(6.0 / 20.0)).abs() < 0.02, "{g}");
        let far = gain_at(Biquad::peaking(sr, 1000.0, 6.0, 2.0), sr, 100.0);
        assert!((far - 1.0).abs() < 0.05, "{far}");
        let bp = gain_at(Biquad::bandpass(sr, 3000.0, 1.0), sr, 3000.0);
        assert!((bp - 1.0).abs() < 0.02);
    }
}
