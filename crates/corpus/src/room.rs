//! The recording chain of the corpus: a violin rendered dry is placed in a room, picked up
//! by one or two microphones, mixed with recording noise, levelled, and optionally
//! re-encoded lossily — all described by one seeded, serialisable [`Recording`] that goes
//! into the manifest.
//!
//! * **room**: a synthetic impulse response per channel (direct sound, first-order image
//!   reflections 3–40 ms, a three-band exponentially decaying tail with RT60 0–2 s whose
//!   level against the direct sound follows the microphone distance 0.3–8 m), applied by
//!   FFT overlap-add convolution; RT60 0 is dry;
//! * **stereo**: two channels with independent tails and a small time (≤ 0.7 ms) and level
//!   (≤ 3 dB) difference;
//! * **noise**: pink noise, mains hum and hiss, each at a drawn SNR of 15–60 dB, or off;
//! * **level**: the item's peak (all channels) is set to −40..−1 dBFS, so it never clips;
//! * **rate**: the render rate is drawn from 22.05–96 kHz (mostly 44.1 and 48 kHz);
//! * **lossy**: three items in ten are re-encoded as MP3 or Ogg Vorbis ([`encode_lossy`]).
//!
//! ```
//! use corpus::room::Recording;
//! use net_core::rng::Rng;
//! let rec = Recording::draw(&mut Rng::new(4));
//! let mono = vec![0.0f32; 100];
//! let channels = rec.apply(&mono, rec.sample_rate_hz)?;
//! assert_eq!(channels.len(), usize::from(rec.channels));
//! # Ok::<(), corpus::room::RoomError>(())
//! ```

mod error;
mod ir;
mod lossy;
mod noise;

use serde::{Deserialize, Serialize};

use net_core::rng::Rng;

pub use error::RoomError;
pub use ir::rt60_schroeder;
pub use lossy::{check_encoders, encode_lossy, LossyEncoding, LossyKind};
pub use noise::{NoiseKind, NoiseSpec};

/// The render rates a recording can be drawn at, with their weights.
pub const SAMPLE_RATES_HZ: [(u32, f64); 6] = [
    (22_050, 0.08),
    (32_000, 0.04),
    (44_100, 0.42),
    (48_000, 0.38),
    (88_200, 0.03),
    (96_000, 0.05),
];

/// One item's recording chain. Every drawn value is stored, so the manifest reproduces it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Recording {
    /// Render and output sample rate, Hz.
    pub sample_rate_hz: u32,
    /// 1 (mono) or 2 (stereo).
    pub channels: u16,
    /// Room length in metres (width 0.72 ×, height 0.3 × + 1.5 m, ≤ 12 m).
    pub room_size_m: f64,
    /// Mid-band reverberation time in seconds; 0 = dry (no room at all).
    pub rt60_s: f64,
    /// Distance from the violin to the microphone, metres.
    pub mic_distance_m: f64,
    /// Direction of the microphone from the violin in the horizontal plane, radians.
    pub mic_angle_rad: f64,
    /// Height of the microphone, metres.
    pub mic_height_m: f64,
    /// Delay of the second channel against the first, ms (negative: the first is later).
    pub interchannel_delay_ms: f64,
    /// Level of the second channel against the first, dB.
    pub interchannel_level_db: f64,
    /// Added noises (empty: none).
    pub noise: Vec<NoiseSpec>,
    /// Peak level of the whole item in dBFS (≤ −1: never clips).
    pub peak_dbfs: f64,
    /// Lossy re-encoding of the written file, if any.
    pub lossy: Option<LossyEncoding>,
    /// Seed of the room tails and noise waveforms.
    pub seed: u64,
}

impl Recording {
    /// No room, no noise, mono, peak at −3 dBFS, no lossy encoding.
    pub fn dry(sample_rate_hz: u32) -> Self {
        Self {
            sample_rate_hz,
            channels: 1,
            room_size_m: 0.0,
            rt60_s: 0.0,
            mic_distance_m: 0.0,
            mic_angle_rad: 0.0,
            mic_height_m: 0.0,
            interchannel_delay_ms: 0.0,
            interchannel_level_db: 0.0,
            noise: Vec::new(),
            peak_dbfs: -3.0,
            lossy: None,
            seed: 0,
        }
    }

    /// A seeded draw (see the module documentation for the ranges). One room in eight is
    /// dry; small rooms get short reverberation (RT60 ≤ 0.3 s + 0.1 s per metre).
    pub fn draw(rng: &mut Rng) -> Self {
        let weights: Vec<f64> = SAMPLE_RATES_HZ.iter().map(|(_, w)| *w).collect();
        let sample_rate_hz = rng
            .weighted(&weights)
            .and_then(|i| SAMPLE_RATES_HZ.get(i))
            .map_or(44_100, |(sr, _)| *sr);
        let channels = if rng.chance(0.5) { 2 } else { 1 };
        let room_size_m = rng.uniform(3f64.ln(), 30f64.ln()).exp();
        let rt60_s = if rng.chance(0.125) {
            0.0
        } else {
            rng.uniform(0.1, (0.3 + 0.1 * room_size_m).min(2.0))
        };
        let mic_distance_m = rng
            .uniform(0.3f64.ln(), (0.6 * room_size_m).min(8.0).ln())
            .exp();
        let mic_angle_rad = rng.uniform(-0.5, 0.5);
        let mic_height_m = rng.uniform(1.0, 2.2);
        let (mut delay, mut level) = (rng.uniform(-0.7, 0.7), rng.uniform(-3.0, 3.0));
        if channels == 1 {
            (delay, level) = (0.0, 0.0);
        }
        let mut noise = Vec::new();
        if rng.chance(0.5) {
            noise.push((NoiseKind::Pink, rng.uniform(15.0, 60.0)));
        }
        if rng.chance(0.3) {
            let mains_hz = if rng.chance(0.5) { 50 } else { 60 };
            noise.push((NoiseKind::Hum { mains_hz }, rng.uniform(15.0, 60.0)));
        }
        if rng.chance(0.5) {
            let cutoff_hz = rng.uniform(2_000.0, 6_000.0);
            noise.push((NoiseKind::Hiss { cutoff_hz }, rng.uniform(15.0, 60.0)));
        }
        let peak_dbfs = rng.uniform(-40.0, -1.0);
        let lossy = rng.chance(0.3).then(|| {
            let serial = (rng.next_u64() >> 33) as u32;
            // MPEG audio stops at 48 kHz: faster rates are always Vorbis.
            if sample_rate_hz <= 48_000 && rng.chance(0.5) {
                let rates = [64, 80, 96, 112, 128, 160, 192];
                let quality = *rng.pick(&rates).unwrap_or(&128);
                LossyEncoding {
                    kind: LossyKind::Mp3,
                    quality,
                    serial,
                }
            } else {
                LossyEncoding {
                    kind: LossyKind::Vorbis,
                    quality: rng.int(0, 6) as u32,
                    serial,
                }
            }
        });
        Self {
            sample_rate_hz,
            channels,
            room_size_m,
            rt60_s,
            mic_distance_m,
            mic_angle_rad,
            mic_height_m,
            interchannel_delay_ms: delay,
            interchannel_level_db: level,
            noise: noise
                .into_iter()
                .map(|(kind, snr_db)| NoiseSpec { kind, snr_db })
                .collect(),
            peak_dbfs,
            lossy,
            seed: rng.next_u64(),
        }
    }

    /// Direct-to-reverberant ratio in dB at the drawn distance (`+∞` when dry).
    pub fn drr_db(&self) -> f64 {
        if self.rt60_s <= 0.0 {
            return f64::INFINITY;
        }
        let r_c = ir::critical_distance_m(self.room_size_m, self.rt60_s);
        20.0 * (r_c / self.mic_distance_m.max(0.05)).log10()
    }

    /// The room impulse response of `channel` (0 or 1) at `sample_rate_hz`, direct sound
    /// first (the propagation delay is left out so audio stays aligned with its labels).
    pub fn impulse_response(&self, channel: usize, sample_rate_hz: u32) -> Vec<f64> {
        let delay_ms = self.interchannel_delay_ms;
        let (delay_s, level_db) = if channel == 0 {
            ((-delay_ms).max(0.0) / 1000.0, 0.0)
        } else {
            (delay_ms.max(0.0) / 1000.0, self.interchannel_level_db)
        };
        let spec = ir::IrSpec {
            room_size_m: self.room_size_m,
            rt60_s: self.rt60_s,
            mic_distance_m: self.mic_distance_m,
            mic_angle_rad: self.mic_angle_rad,
            mic_height_m: self.mic_height_m,
            delay_s,
            level_db,
            seed: Rng::new(self.seed).fork(10 + channel as u64).next_u64(),
        };
        ir::impulse_response(&spec, f64::from(sample_rate_hz))
    }

    /// Records `mono` (at `sample_rate_hz`): one `Vec` per channel (`self.channels` of them),
    /// each as long as the input — the reverberation past the end is cut, as the labels end
    /// there. Non-finite input samples count as silence.
    ///
    /// The noises' SNRs are measured against the reverberant signal's power over the whole
    /// item and all channels; then everything is scaled so the item's peak is `peak_dbfs`.
    /// A silent input gets its noise at −100 dBFS − SNR and is not amplified. An empty
    /// input gives empty channels.
    pub fn apply(&self, mono: &[f32], sample_rate_hz: u32) -> Result<Vec<Vec<f32>>, RoomError> {
        if !(8_000..=384_000).contains(&sample_rate_hz) {
            return Err(RoomError::SampleRate(sample_rate_hz));
        }
        let n_ch = usize::from(self.channels.clamp(1, 2));
        let sr = f64::from(sample_rate_hz);
        let dry: Vec<f64> = mono
            .iter()
            .map(|x| if x.is_finite() { f64::from(*x) } else { 0.0 })
            .collect();
        let mut chans = Vec::with_capacity(n_ch);
        for c in 0..n_ch {
            chans.push(ir::convolve(
                &dry,
                &self.impulse_response(c, sample_rate_hz),
            )?);
        }
        let n = dry.len();
        let total = (n * n_ch).max(1) as f64;
        let power = chans.iter().flatten().map(|x| x * x).sum::<f64>() / total;
        let silent = power < 1e-20;
        let reference = if silent { 1e-10 } else { power };
        let root = Rng::new(self.seed);
        for (k, spec) in self.noise.iter().enumerate() {
            let level = (reference / 10f64.powf(spec.snr_db / 10.0)).sqrt();
            for (c, chan) in chans.iter_mut().enumerate() {
                // Hum is the same in both channels (one mains); the rest is independent.
                let stream = if matches!(spec.kind, NoiseKind::Hum { .. }) {
                    100 + k as u64
                } else {
                    100 + k as u64 + 1000 * c as u64
                };
                let noise = noise::unit_noise(&spec.kind, n, sr, &mut root.fork(stream));
                for (x, v) in chan.iter_mut().zip(&noise) {
                    *x += level * v;
                }
            }
        }
        let peak = chans.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        let target = 10f64.powf(self.peak_dbfs.min(-0.01) / 20.0);
        let gain = if peak > 0.0 && !silent {
            target / peak
        } else {
            1.0
        };
        Ok(chans
            .into_iter()
            .map(|c| c.into_iter().map(|x| (x * gain) as f32).collect())
            .collect())
    }
}

#[cfg(test)]
mod tests;
