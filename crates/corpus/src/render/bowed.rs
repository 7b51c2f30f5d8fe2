//! The built-in bowed-string synthesizer: an additive model of a bowed string (Helmholtz
//! motion's sawtooth-like spectrum, brighter with more bow pressure), bow noise, and a
//! fixed body-resonance filter.
//!
//! What matters for the labels is reproduced on purpose:
//! * a **bow change** ends the old stroke with a fast decay and starts the new one with an
//!   attack transient and a noise burst, so the amplitude dips and re-attacks;
//! * a **slurred** note change keeps one continuous stroke: the pitch glides to the new
//!   note in ~25 ms under an unbroken amplitude envelope — no attack, no burst; a slurred
//!   note on the *same* pitch is played portato (the level dips and swells,
//!   [`portato_gain`](crate::render::portato_gain)), as a tie would otherwise be inaudible;
//! * **vibrato** (5–7 Hz, 10–25 cents) fades in 0.12–0.3 s after a stopped note's onset;
//!   open strings have none;
//! * **dynamics** set both the level and the brightness (spectral tilt), as bow pressure
//!   and speed do.

use crate::render::biquad::Biquad;
use crate::render::portato::portato_gain;
use crate::render::renderer::{RenderError, RenderSettings, Renderer};
use net_core::rng::Rng;
use performance::{TimedNote, Timeline};

/// Tunable constants of the synthesizer.
#[derive(Debug, Clone, PartialEq)]
pub struct BowedConfig {
    /// Glide time between slurred notes, seconds.
    pub slur_glide_s: f64,
    /// Release time when the bow stops on the string before a rest, seconds (short: the
    /// corpus labels everything after a note's offset + 0.2 s as silence).
    pub release_s: f64,
    /// Decay time of the old stroke at a bow change, seconds.
    pub change_decay_s: f64,
    /// Peak vibrato depth range in cents.
    pub vibrato_cents: (f64, f64),
    /// Highest harmonic number rendered.
    pub max_harmonics: usize,
}

impl Default for BowedConfig {
    fn default() -> Self {
        Self {
            slur_glide_s: 0.025,
            release_s: 0.03,
            change_decay_s: 0.012,
            vibrato_cents: (10.0, 25.0),
            max_harmonics: 40,
        }
    }
}

/// The built-in renderer (no external files).
#[derive(Debug, Clone, Default)]
pub struct BowedStringSynth {
    /// Its constants.
    pub config: BowedConfig,
}

/// A bow stroke: consecutive notes under one bow.
struct Stroke<'a> {
    notes: &'a [TimedNote],
    /// The next stroke starts right after this one (a bow change, not a rest).
    followed_by_change: bool,
}

fn strokes(notes: &[TimedNote]) -> Vec<Stroke<'_>> {
    let mut out = Vec::new();
    let mut start = 0;
    for i in 1..=notes.len() {
        if i == notes.len() || notes[i].bow_change {
            let followed_by_change = notes
                .get(i)
                .is_some_and(|n| n.note.onset_s - notes[i - 1].note.offset_s < 0.1);
            out.push(Stroke {
                notes: &notes[start..i],
                followed_by_change,
            });
            start = i;
        }
    }
    out
}

/// Capacity of the harmonic weight table.
const MAX_HARMONICS: usize = 64;

fn midi_hz(midi: f64) -> f64 {
    440.0 * 2f64.powf((midi - 69.0) / 12.0)
}

/// Level (linear amplitude) for a dynamic 0..=1: about 30 dB from pp to ff.
fn level(dynamic: f32) -> f64 {
    0.02 + 0.3 * f64::from(dynamic).powf(1.4)
}

impl Renderer for BowedStringSynth {
    fn name(&self) -> &'static str {
        "builtin"
    }

    fn render(
        &self,
        timeline: &Timeline,
        settings: &RenderSettings,
    ) -> Result<Vec<f32>, RenderError> {
        settings.validate()?;
        let sr = f64::from(settings.sample_rate_hz);
        let n_samples = (timeline.duration_s * sr).ceil() as usize;
        let mut out = vec![0.0f64; n_samples];
        let mut rng = Rng::new(settings.seed);
        let tune = 2f64.powf(settings.tuning_cents / 1200.0);
        for stroke in strokes(&timeline.notes) {
            self.render_stroke(&stroke, sr, tune, &mut rng, &mut out);
        }
        // Body resonances: air mode, main wood mode, a dip, the bridge hill, upper roll-off.
        let mut body = [
            Biquad::peaking(sr, 275.0, 8.0, 2.5),
            Biquad::peaking(sr, 460.0, 6.0, 3.0),
            Biquad::peaking(sr, 1_000.0, -3.0, 1.5),
            Biquad::peaking(sr, 2_800.0, 7.0, 1.2),
            Biquad::peaking(sr, 6_000.0, -9.0, 0.7),
        ];
        Ok(out
            .into_iter()
            .map(|x| body.iter_mut().fold(x, |v, f| f.process(v)) as f32)
            .collect())
    }
}

impl BowedStringSynth {
    fn render_stroke(
        &self,
        stroke: &Stroke<'_>,
        sr: f64,
        tune: f64,
        rng: &mut Rng,
        out: &mut [f64],
    ) {
        let cfg = &self.config;
        let Some(first) = stroke.notes.first() else {
            return;
        };
        let Some(last) = stroke.notes.last() else {
            return;
        };
        let start = first.note.onset_s;
        let end = last.note.offset_s;
        let decay = if stroke.followed_by_change {
            cfg.change_decay_s
        } else {
            cfg.release_s
        };
        let tail_end = end + 7.0 * decay;
        let i0 = (start * sr).floor().max(0.0) as usize;
        let i1 = ((tail_end * sr).ceil() as usize).min(out.len());
        let attack_s = if first.accent {
            0.008
        } else {
            rng.uniform(0.012, 0.025)
        };
        let burst_level = if first.accent { 0.5 } else { 0.3 };
        // Per-note vibrato parameters, drawn up front so the stream does not depend on timing.
        let vib: Vec<(f64, f64, f64, f64)> = stroke
            .notes
            .iter()
            .map(|n| {
                let open = n.note.fingering.is_some_and(|f| f.is_open());
                let depth = if open || n.note.offset_s - n.note.onset_s < 0.25 {
                    0.0
                } else {
                    rng.uniform(cfg.vibrato_cents.0, cfg.vibrato_cents.1)
                };
                (
                    depth,
                    rng.uniform(5.0, 7.0),
                    rng.uniform(0.12, 0.3),
                    rng.uniform(0.0, std::f64::consts::TAU),
                )
            })
            .collect();
        let mut noise_bp = Biquad::bandpass(sr, rng.uniform(2_500.0, 4_500.0), 0.8);
        let mut noise_state = rng.next_u64() | 1;
        let mut phase = rng.uniform(0.0, std::f64::consts::TAU);
        let mut smoothed_level = level(first.dynamic);
        let level_coeff = 1.0 - (-1.0 / (0.02 * sr)).exp();
        let mut note_idx = 0usize;
        let mut weights = [0.0f64; MAX_HARMONICS];
        let mut cached = (usize::MAX, 0usize);
        let dt = 1.0 / sr;
        for (i, sample) in out.iter_mut().enumerate().take(i1).skip(i0) {
            let t = i as f64 * dt;
            while note_idx + 1 < stroke.notes.len() && t >= stroke.notes[note_idx + 1].note.onset_s
            {
                note_idx += 1;
            }
            let note = &stroke.notes[note_idx];
            // Pitch: glide from the previous slurred note, then vibrato.
            let mut midi = f64::from(note.note.midi);
            if note_idx > 0 {
                let since = t - note.note.onset_s;
                if since < cfg.slur_glide_s {
                    let x = since / cfg.slur_glide_s;
                    let s = x * x * (3.0 - 2.0 * x);
                    midi = f64::from(stroke.notes[note_idx - 1].note.midi) * (1.0 - s) + midi * s;
                }
            }
            let (depth, rate, delay, vphase) = vib[note_idx];
            let since_onset = t - note.note.onset_s;
            if depth > 0.0 && since_onset > delay {
                let ramp = ((since_onset - delay) / 0.2).min(1.0);
                midi += ramp * depth / 100.0
                    * (std::f64::consts::TAU * rate * (since_onset - delay) + vphase).sin();
            }
            let f0 = midi_hz(midi) * tune;
            phase = (phase + std::f64::consts::TAU * f0 * dt) % std::f64::consts::TAU;
            // Amplitude: attack at the stroke start, level follows the notes' dynamics,
            // decay after the stroke ends.
            smoothed_level += level_coeff * (level(note.dynamic) - smoothed_level);
            let since_start = t - start;
            let attack = 1.0 - (-since_start / attack_s).exp();
            let release = if t > end {
                (-(t - end) / decay).exp()
            } else {
                1.0
            };
            let portato = portato_gain(stroke.notes, note_idx, t);
            let amp = smoothed_level * attack * release * portato;
            if amp < 1e-7 {
                continue;
            }
            // Harmonics by the Chebyshev recurrence sin((h+1)φ) = 2cosφ·sin(hφ) − sin((h−1)φ);
            // the weights h^-brightness are recomputed only when the note or count changes.
            let n_harm = ((0.45 * sr / f0) as usize).clamp(1, cfg.max_harmonics.min(MAX_HARMONICS));
            if cached != (note_idx, n_harm) {
                cached = (note_idx, n_harm);
                let brightness = 1.35 - 0.5 * f64::from(note.dynamic);
                let mut sum = 0.0;
                for (h, w) in weights.iter_mut().enumerate().take(n_harm) {
                    *w = ((h + 1) as f64).powf(-brightness);
                    sum += *w;
                }
                let norm = 1.0 / sum.sqrt();
                for w in weights.iter_mut().take(n_harm) {
                    *w *= norm;
                }
            }
            let (s1, c1) = phase.sin_cos();
            let two_c = 2.0 * c1;
            let (mut prev, mut cur) = (0.0, s1);
            let mut tone = 0.0;
            for w in &weights[..n_harm] {
                tone += w * cur;
                let next = two_c * cur - prev;
                prev = cur;
                cur = next;
            }
            // Bow noise: a steady hiss plus a burst at the stroke's start.
            noise_state ^= noise_state << 13;
            noise_state ^= noise_state >> 7;
            noise_state ^= noise_state << 17;
            let white = (noise_state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
            let burst = burst_level * (-since_start / 0.025).exp();
            let hiss = noise_bp.process(white) * (0.04 + burst);
            *sample += amp * (tone + hiss);
        }
    }
}
