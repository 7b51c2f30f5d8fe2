//! What the synthetic violin renders and what it returns: [`SynthConfig`], [`SynthPiece`],
//! [`SynthNote`] and the seeded [`Rng`].

use serde::{Deserialize, Serialize};

pub use performance::Meter as TimeSignature;

/// What to render. All durations in seconds, levels in dB.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SynthConfig {
    /// Seed of every random choice.
    pub seed: u64,
    /// Output sample rate in Hz.
    pub sample_rate_hz: u32,
    /// Mean tempo in beats per minute (the beat of [`TimeSignature`]).
    pub tempo_bpm: f64,
    /// Metre.
    pub time_signature: TimeSignature,
    /// Number of bars.
    pub bars: usize,
    /// Relative tempo swing of the rubato curve (0.08 = ±8 %).
    pub rubato: f64,
    /// Vibrato depth range (peak deviation) in cents.
    pub vibrato_cents: (f64, f64),
    /// Vibrato rate range in Hz.
    pub vibrato_hz: (f64, f64),
    /// Probability that a note is slurred to the previous one (no re-attack).
    pub slur_prob: f64,
    /// Probability that a note repeats the previous pitch (always re-attacked).
    pub repeat_prob: f64,
    /// Probability that an off-downbeat note is a rest.
    pub rest_prob: f64,
    /// Extra level of notes starting on a downbeat.
    pub downbeat_accent_db: f64,
    /// Level of the white noise floor relative to the loudest note.
    pub noise_floor_db: f64,
    /// Silence before the first and after the last note.
    pub padding_s: f64,
}

impl Default for SynthConfig {
    fn default() -> Self {
        Self {
            seed: 1,
            sample_rate_hz: 22_050,
            tempo_bpm: 100.0,
            time_signature: TimeSignature::FOUR_FOUR,
            bars: 8,
            rubato: 0.05,
            vibrato_cents: (30.0, 50.0),
            vibrato_hz: (5.0, 7.0),
            slur_prob: 0.3,
            repeat_prob: 0.15,
            rest_prob: 0.05,
            downbeat_accent_db: 5.0,
            noise_floor_db: -60.0,
            padding_s: 0.5,
        }
    }
}

impl SynthConfig {
    /// A varied configuration drawn from `seed`: tempo 60–160 bpm, a metre among 2/4, 3/4,
    /// 4/4 and 6/8, and as many bars as fit in about `seconds`.
    pub fn varied(seed: u64, seconds: f64) -> SynthConfig {
        let mut rng = Rng::new(seed ^ 0x5eed_cafe);
        let time_signature = [
            TimeSignature::FOUR_FOUR,
            TimeSignature::THREE_FOUR,
            TimeSignature::TWO_FOUR,
            TimeSignature::SIX_EIGHT,
        ][rng.below(4)];
        let tempo_bpm = if time_signature.subdivisions == 3 {
            rng.uniform(50.0, 80.0)
        } else {
            rng.uniform(60.0, 160.0)
        };
        let bar_s = 60.0 / tempo_bpm * f64::from(time_signature.beats_per_bar);
        SynthConfig {
            seed,
            tempo_bpm,
            time_signature,
            bars: ((seconds / bar_s).round() as usize).max(1),
            ..SynthConfig::default()
        }
    }
}

/// One note of the ground truth.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SynthNote {
    /// When the note starts (its glide starts, for a slurred note), in seconds.
    pub onset_s: f64,
    /// When it stops sounding, in seconds.
    pub offset_s: f64,
    /// MIDI pitch.
    pub midi: u8,
    /// Joined to the previous note without a re-attack.
    pub slurred: bool,
}

/// Rendered audio and its exact labels.
#[derive(Debug, Clone, PartialEq)]
pub struct SynthPiece {
    /// Mono samples, peak 0.9.
    pub samples: Vec<f32>,
    /// Sample rate in Hz.
    pub sample_rate_hz: u32,
    /// The notes in time order.
    pub notes: Vec<SynthNote>,
    /// Every beat, in seconds.
    pub beats_s: Vec<f64>,
    /// The first beat of every bar, in seconds.
    pub downbeats_s: Vec<f64>,
    /// Mean tempo in bpm.
    pub tempo_bpm: f64,
    /// Metre.
    pub time_signature: TimeSignature,
    /// Instantaneous f0 of every sample in Hz (glides and vibrato included), 0 where no
    /// note sounds.
    pub f0_hz: Vec<f32>,
}

impl SynthPiece {
    /// Duration in seconds.
    pub fn duration_s(&self) -> f64 {
        self.samples.len() as f64 / f64::from(self.sample_rate_hz)
    }

    /// Reference f0 at the times `t · hop_s` for `n_frames` frames, 0 where unvoiced (the
    /// mir_eval convention).
    pub fn reference_f0(&self, hop_s: f64, n_frames: usize) -> Vec<f32> {
        let sr = f64::from(self.sample_rate_hz);
        (0..n_frames)
            .map(|t| {
                let i = (t as f64 * hop_s * sr).round() as usize;
                self.f0_hz.get(i).copied().unwrap_or(0.0)
            })
            .collect()
    }
}

/// SplitMix64: small, fast, seeded; good enough for synthetic test material.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from `seed`.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform integer in 0..n (0 when n is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.unit() * n as f64) as usize % n
        }
    }

    /// `true` with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = self.unit().max(1e-300);
        let u2 = self.unit();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
}
