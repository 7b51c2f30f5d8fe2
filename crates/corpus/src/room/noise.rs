//! Recording noises: pink noise, mains hum, high-passed hiss — each generated at unit RMS
//! and then scaled to its drawn signal-to-noise ratio.

use serde::{Deserialize, Serialize};

use net_core::rng::Rng;

/// The kind of an added noise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum NoiseKind {
    /// 1/f noise (Voss–McCartney: 16 octave-spaced random rows summed).
    Pink,
    /// Mains hum: the fundamental and six harmonics of the mains frequency.
    Hum {
        /// 50 or 60 Hz.
        mains_hz: u32,
    },
    /// White noise high-passed (two one-pole sections) above `cutoff_hz`: preamp hiss.
    Hiss {
        /// High-pass corner in Hz.
        cutoff_hz: f64,
    },
}

/// One noise added to a recording.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NoiseSpec {
    /// Which noise.
    pub kind: NoiseKind,
    /// Signal-to-noise ratio in dB (signal power over the whole item, all channels).
    pub snr_db: f64,
}

/// Rows of the Voss–McCartney generator.
const PINK_ROWS: usize = 16;

/// `n` samples of `kind` at `sr` Hz with an RMS of exactly 1 (all zeros for `n` = 0).
pub(crate) fn unit_noise(kind: &NoiseKind, n: usize, sr: f64, rng: &mut Rng) -> Vec<f64> {
    let mut out = match kind {
        NoiseKind::Pink => pink(n, rng),
        NoiseKind::Hum { mains_hz } => hum(n, sr, f64::from(*mains_hz), rng),
        NoiseKind::Hiss { cutoff_hz } => hiss(n, sr, *cutoff_hz, rng),
    };
    let mean = out.iter().sum::<f64>() / n.max(1) as f64;
    let rms = (out.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n.max(1) as f64).sqrt();
    let scale = if rms > 0.0 { 1.0 / rms } else { 0.0 };
    for x in &mut out {
        *x = (*x - mean) * scale;
    }
    out
}

/// Voss–McCartney: row `k` is redrawn every 2^k samples (the row given by the count's
/// trailing zeros), so each row covers one octave of the spectrum; a white row adds the top.
fn pink(n: usize, rng: &mut Rng) -> Vec<f64> {
    let mut rows = [0.0f64; PINK_ROWS];
    for r in &mut rows {
        *r = rng.uniform(-1.0, 1.0);
    }
    let mut sum: f64 = rows.iter().sum();
    (0..n)
        .map(|i| {
            let k = (i + 1).trailing_zeros() as usize;
            if k < PINK_ROWS {
                let new = rng.uniform(-1.0, 1.0);
                sum += new - rows[k];
                rows[k] = new;
            }
            sum + rng.uniform(-1.0, 1.0)
        })
        .collect()
}

/// Odd harmonics stronger than even ones (as transformer saturation makes them), random
/// phases and levels, and a slow ±0.1 % drift of the mains frequency.
fn hum(n: usize, sr: f64, mains_hz: f64, rng: &mut Rng) -> Vec<f64> {
    let harmonics: Vec<(f64, f64, f64)> = (1..=7)
        .map(|k| {
            let level = if k == 1 {
                1.0
            } else if k % 2 == 1 {
                rng.uniform(0.2, 0.7) / f64::from(k).sqrt()
            } else {
                rng.uniform(0.02, 0.25) / f64::from(k)
            };
            (f64::from(k), level, rng.uniform(0.0, std::f64::consts::TAU))
        })
        .filter(|(k, _, _)| k * mains_hz < 0.45 * sr)
        .collect();
    let drift_hz = rng.uniform(0.05, 0.3);
    let drift_phase = rng.uniform(0.0, std::f64::consts::TAU);
    let mut phase = 0.0f64;
    (0..n)
        .map(|i| {
            let t = i as f64 / sr;
            let f = mains_hz
                * (1.0 + 0.001 * (std::f64::consts::TAU * drift_hz * t + drift_phase).sin());
            phase = (phase + std::f64::consts::TAU * f / sr) % std::f64::consts::TAU;
            harmonics
                .iter()
                .map(|(k, a, p)| a * (k * phase + p).sin())
                .sum()
        })
        .collect()
}

fn hiss(n: usize, sr: f64, cutoff_hz: f64, rng: &mut Rng) -> Vec<f64> {
    let a = (-std::f64::consts::TAU * cutoff_hz.clamp(20.0, 0.4 * sr) / sr).exp();
    let (mut x1, mut y1, mut z1, mut w1) = (0.0, 0.0, 0.0, 0.0);
    (0..n)
        .map(|_| {
            let x = rng.uniform(-1.0, 1.0);
            // Two one-pole high-passes: y[n] = a (y[n−1] + x[n] − x[n−1]).
            let y = a * (y1 + x - x1);
            x1 = x;
            y1 = y;
            let w = a * (w1 + y - z1);
            z1 = y;
            w1 = w;
            w
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn band_power(x: &[f64], sr: f64, hz: f64) -> f64 {
        // Goertzel-style single-bin power.
        let w = std::f64::consts::TAU * hz / sr;
        let (mut re, mut im) = (0.0, 0.0);
        for (i, v) in x.iter().enumerate() {
            re += v * (w * i as f64).cos();
            im += v * (w * i as f64).sin();
        }
        (re * re + im * im) / x.len() as f64
    }

    #[test]
    fn every_kind_has_unit_rms_and_the_right_colour() {
        let sr = 44_100.0;
        let n = 1 << 16;
        for kind in [
            NoiseKind::Pink,
            NoiseKind::Hum { mains_hz: 50 },
            NoiseKind::Hiss { cutoff_hz: 3_000.0 },
        ] {
            let x = unit_noise(&kind, n, sr, &mut Rng::new(3));
            let rms = (x.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
            assert!((rms - 1.0).abs() < 1e-9, "{kind:?}");
            assert!(x.iter().all(|v| v.is_finite()));
        }
        let pink = unit_noise(&NoiseKind::Pink, n, sr, &mut Rng::new(4));
        let low: f64 = (1..20)
            .map(|k| band_power(&pink, sr, 100.0 + f64::from(k)))
            .sum();
        let high: f64 = (1..20)
            .map(|k| band_power(&pink, sr, 8_000.0 + f64::from(k)))
            .sum();
        assert!(low > 5.0 * high, "pink: {low} vs {high}");
        let hum = unit_noise(&NoiseKind::Hum { mains_hz: 60 }, n, sr, &mut Rng::new(5));
        assert!(band_power(&hum, sr, 60.0) > 100.0 * band_power(&hum, sr, 400.0));
        let hiss = unit_noise(
            &NoiseKind::Hiss { cutoff_hz: 4_000.0 },
            n,
            sr,
            &mut Rng::new(6),
        );
        let lo: f64 = (1..20)
            .map(|k| band_power(&hiss, sr, 200.0 + f64::from(k)))
            .sum();
        let hi: f64 = (1..20)
            .map(|k| band_power(&hiss, sr, 10_000.0 + f64::from(k)))
            .sum();
        assert!(hi > 10.0 * lo, "hiss: {lo} vs {hi}");
    }
}
