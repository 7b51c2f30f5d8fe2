//! Seeded augmentation of rendered audio: room reverb, gain, a noise floor. (Tuning offsets
//! and the sample rate are chosen before rendering, see [`Augmentation`].)

use serde::{Deserialize, Serialize};

use net_core::rng::Rng;

/// The augmentation drawn for one item.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Augmentation {
    /// Output sample rate in Hz (22 050, 32 000, 44 100 or 48 000).
    pub sample_rate_hz: u32,
    /// Tuning offset in cents applied by the renderer (labels keep nominal pitches).
    pub tuning_cents: f64,
    /// Gain in dB applied after normalisation to a −3 dBFS peak.
    pub gain_db: f64,
    /// Reverb: wet share 0..1 (0 = dry).
    pub reverb_wet: f64,
    /// Reverb decay time (RT60) in seconds.
    pub reverb_rt60_s: f64,
    /// White noise floor in dBFS (−∞ = none is written as −200).
    pub noise_dbfs: f64,
}

impl Augmentation {
    /// No augmentation at `sample_rate_hz`.
    pub fn none(sample_rate_hz: u32) -> Self {
        Self {
            sample_rate_hz,
            tuning_cents: 0.0,
            gain_db: 0.0,
            reverb_wet: 0.0,
            reverb_rt60_s: 0.5,
            noise_dbfs: -200.0,
        }
    }

    /// A seeded draw: rates 22.05–48 kHz, ±10 cents tuning, −12..0 dB gain, reverb on two
    /// items in three (wet 5–35 %, RT60 0.3–1.6 s), noise floor −75..−45 dBFS.
    pub fn draw(rng: &mut Rng) -> Self {
        let sample_rate_hz = *rng
            .pick(&[22_050, 32_000, 44_100, 48_000])
            .unwrap_or(&22_050);
        Self {
            sample_rate_hz,
            tuning_cents: rng.uniform(-10.0, 10.0),
            gain_db: rng.uniform(-12.0, 0.0),
            reverb_wet: if rng.chance(0.66) {
                rng.uniform(0.05, 0.35)
            } else {
                0.0
            },
            reverb_rt60_s: rng.uniform(0.3, 1.6),
            noise_dbfs: rng.uniform(-75.0, -45.0),
        }
    }

    /// Applies reverb, peak normalisation to −3 dBFS, gain and the noise floor in place.
    pub fn apply(&self, audio: &mut [f32], seed: u64) {
        if self.reverb_wet > 0.0 {
            reverb(
                audio,
                self.sample_rate_hz,
                self.reverb_rt60_s,
                self.reverb_wet,
            );
        }
        let peak = audio.iter().fold(0.0f32, |m, x| m.max(x.abs()));
        let target = 10f64.powf((-3.0 + self.gain_db) / 20.0);
        let scale = if peak > 0.0 {
            target / f64::from(peak)
        } else {
            1.0
        };
        let noise = 10f64.powf(self.noise_dbfs / 20.0) * 3f64.sqrt();
        let mut rng = Rng::new(seed ^ 0xA5A5_5A5A);
        for x in audio.iter_mut() {
            *x = (f64::from(*x) * scale + noise * rng.uniform(-1.0, 1.0)) as f32;
        }
    }
}

/// Schroeder reverb: four parallel feedback combs (delays 29.7–43.7 ms, feedback from the
/// RT60) into two series all-passes, mixed with the dry signal.
fn reverb(audio: &mut [f32], sample_rate_hz: u32, rt60_s: f64, wet: f64) {
    let sr = f64::from(sample_rate_hz);
    let comb_ms = [29.7, 37.1, 41.1, 43.7];
    let mut combs: Vec<(Vec<f64>, usize, f64)> = comb_ms
        .iter()
        .map(|ms| {
            let len = ((ms / 1000.0) * sr) as usize;
            let g = 10f64.powf(-3.0 * (ms / 1000.0) / rt60_s.max(0.05));
            (vec![0.0; len.max(1)], 0usize, g)
        })
        .collect();
    let mut allpasses: Vec<(Vec<f64>, usize)> = [5.0, 1.7]
        .iter()
        .map(|ms| (vec![0.0; (((ms / 1000.0) * sr) as usize).max(1)], 0usize))
        .collect();
    for x in audio.iter_mut() {
        let input = f64::from(*x);
        let mut sum = 0.0;
        for (buf, pos, g) in combs.iter_mut() {
            let y = buf[*pos];
            buf[*pos] = input + *g * y;
            *pos = (*pos + 1) % buf.len();
            sum += y;
        }
        let mut y = sum * 0.25;
        for (buf, pos) in allpasses.iter_mut() {
            let delayed = buf[*pos];
            let v = y + 0.7 * delayed;
            buf[*pos] = v;
            *pos = (*pos + 1) % buf.len();
            y = delayed - 0.7 * v;
        }
        *x = ((1.0 - wet) * input + wet * y) as f32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalises_and_adds_a_floor() {
        let mut a = vec![0.0f32; 1000];
        a[10] = 0.1;
        let aug = Augmentation {
            noise_dbfs: -60.0,
            ..Augmentation::none(22_050)
        };
        aug.apply(&mut a, 1);
        let peak = a.iter().fold(0.0f32, |m, x| m.max(x.abs()));
        assert!((f64::from(peak) - 10f64.powf(-3.0 / 20.0)).abs() < 0.01);
        let rms = (a[500..].iter().map(|x| x * x).sum::<f32>() / 500.0).sqrt();
        assert!((20.0 * f64::from(rms).log10() + 60.0).abs() < 3.0);
    }

    #[test]
    fn reverb_adds_a_decaying_tail() {
        let mut a = vec![0.0f32; 22_050];
        a[0] = 1.0;
        reverb(&mut a, 22_050, 0.5, 0.5);
        let early: f32 = a[1000..3000].iter().map(|x| x.abs()).sum();
        let late: f32 = a[15_000..17_000].iter().map(|x| x.abs()).sum();
        assert!(early > 0.0 && late < early * 0.2);
    }
}
