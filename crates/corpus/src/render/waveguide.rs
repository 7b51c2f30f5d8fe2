//! A digital-waveguide bowed string ([`WaveguideViolin`]): the string is two delay lines
//! split at the bow, excited through a friction law by a bow whose velocity and force
//! follow the strokes, and heard through a violin-body filter.
//!
//! What a stroke does to the string is played out physically rather than drawn as an
//! envelope:
//! * a **bow change** decelerates the bow to rest at the end of a stroke and accelerates it
//!   the other way (a real reversal of the velocity's sign) — the Helmholtz motion collapses
//!   and rebuilds, so the level dips and the spectrum changes at every change;
//! * a **slurred** note keeps the bow moving and only shortens or lengthens the string
//!   (a glide of 10–30 ms, as a finger lands), without any reversal;
//! * **dynamics** 0..1 set bow velocity and force; **accents** add a force and speed bump
//!   with a fast attack;
//! * **vibrato** (4.5–7 Hz, 5–30 cents) begins after a delay on stopped notes; open strings
//!   (`note.fingering` on an open string) have none; each note is detuned by up to ±5 cents.
//!
//! Every choice (bow position, force, noise, body, per-note detuning and vibrato) comes
//! from `RenderSettings::seed`, so a seed gives bit-identical samples.

use crate::render::biquad::Biquad;
use crate::render::renderer::{RenderError, RenderSettings, Renderer};
use crate::render::waveguide_string::{BowInput, BowedString};
use net_core::rng::Rng;
use performance::{TimedNote, Timeline};

/// Ranges the per-item and per-note draws come from.
#[derive(Debug, Clone, PartialEq)]
pub struct WaveguideConfig {
    /// Bow position as a fraction of the string length from the bridge.
    pub beta: (f64, f64),
    /// Base bow force 0..1 at a dynamic of 1.
    pub force: (f64, f64),
    /// Bow-velocity attack time at a stroke's start, seconds (accents use the low end).
    pub attack_s: (f64, f64),
    /// Relative bow-velocity noise (standard deviation).
    pub bow_noise: (f64, f64),
    /// Vibrato rate, Hz.
    pub vibrato_hz: (f64, f64),
    /// Vibrato depth, cents.
    pub vibrato_cents: (f64, f64),
    /// Delay before vibrato starts, seconds after the onset.
    pub vibrato_delay_s: (f64, f64),
    /// Largest per-note detuning, cents (drawn in ±this).
    pub detune_cents: f64,
    /// Glide time between slurred notes, seconds.
    pub glide_s: (f64, f64),
    /// Free decay (T60) of the string while it is bowed or stopped, seconds.
    pub string_t60_s: (f64, f64),
    /// Decay (T60) once the bow leaves the string and the finger damps it, seconds.
    pub damp_t60_s: (f64, f64),
    /// Output gain (linear) applied after the body filter.
    pub output_gain: f64,
}

impl Default for WaveguideConfig {
    fn default() -> Self {
        Self {
            beta: (0.08, 0.2),
            force: (0.35, 0.8),
            attack_s: (0.02, 0.12),
            bow_noise: (0.005, 0.03),
            vibrato_hz: (4.5, 7.0),
            vibrato_cents: (5.0, 30.0),
            vibrato_delay_s: (0.1, 0.35),
            detune_cents: 5.0,
            glide_s: (0.01, 0.03),
            string_t60_s: (0.8, 2.0),
            damp_t60_s: (0.06, 0.12),
            output_gain: 0.3,
        }
    }
}

/// The waveguide renderer (name `"waveguide"`, no external files).
///
/// ```
/// use corpus::render::{RenderSettings, Renderer, WaveguideViolin};
/// use performance::{Note, TimedNote, Timeline};
/// let note = TimedNote { note: Note::new(0.1, 0.6, 69), bow_change: true, dynamic: 0.7, accent: false };
/// let timeline = Timeline { duration_s: 1.0, notes: vec![note], beats_s: vec![], downbeats_s: vec![],
///     arousal_2hz: vec![], tempo_bpm: 120.0 };
/// let audio = WaveguideViolin::default().render(&timeline, &RenderSettings::default())?;
/// assert_eq!(audio.len(), 22_050);
/// # Ok::<(), corpus::render::RenderError>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct WaveguideViolin {
    /// Its draw ranges.
    pub config: WaveguideConfig,
}

/// Everything decided about one note before rendering.
#[derive(Debug, Clone)]
struct NotePlan {
    onset: f64,
    offset: f64,
    /// Loop period in samples, detuning included.
    period: f64,
    /// Period of the previous note when this one is slurred to it.
    glide_from: Option<f64>,
    glide_s: f64,
    vibrato: Option<(f64, f64, f64, f64)>,
    dynamic: f64,
    accent: bool,
    stroke: usize,
}

/// One bow stroke.
#[derive(Debug, Clone)]
struct StrokePlan {
    start: f64,
    end: f64,
    /// +1 down-bow, −1 up-bow.
    direction: f64,
    attack_s: f64,
    beta: f64,
}

fn midi_hz(midi: f64) -> f64 {
    440.0 * 2f64.powf((midi - 69.0) / 12.0)
}

fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Per-item draws.
struct ItemDraw {
    beta: f64,
    force: f64,
    noise: f64,
    lp_a: f64,
    string_t60: f64,
    damp_t60: f64,
    velocity_scale: f64,
}

impl WaveguideViolin {
    fn plan(
        &self,
        notes: &[TimedNote],
        sr: f64,
        tune: f64,
        item: &ItemDraw,
        rng: &Rng,
    ) -> (Vec<NotePlan>, Vec<StrokePlan>) {
        let cfg = &self.config;
        let mut plans: Vec<NotePlan> = Vec::with_capacity(notes.len());
        let mut strokes: Vec<StrokePlan> = Vec::new();
        for (i, n) in notes.iter().enumerate() {
            let mut r = rng.fork(1000 + i as u64);
            let detune = r.uniform(-cfg.detune_cents, cfg.detune_cents);
            let hz = midi_hz(f64::from(n.note.midi) + detune / 100.0) * tune;
            let period = (sr / hz).max(2.0);
            let open = n.note.fingering.is_some_and(|f| f.is_open());
            let vib = (
                r.uniform(cfg.vibrato_cents.0, cfg.vibrato_cents.1),
                r.uniform(cfg.vibrato_hz.0, cfg.vibrato_hz.1),
                r.uniform(cfg.vibrato_delay_s.0, cfg.vibrato_delay_s.1),
                r.uniform(0.0, std::f64::consts::TAU),
            );
            let glide_s = r.uniform(cfg.glide_s.0, cfg.glide_s.1);
            let attack_s = if n.accent {
                r.uniform(0.008, 0.02)
            } else {
                r.uniform(cfg.attack_s.0, cfg.attack_s.1)
            };
            let beta = (item.beta + r.uniform(-0.015, 0.015)).clamp(cfg.beta.0, cfg.beta.1);
            let new_stroke = n.bow_change || strokes.is_empty();
            if new_stroke {
                let direction = if strokes.len().is_multiple_of(2) {
                    1.0
                } else {
                    -1.0
                };
                strokes.push(StrokePlan {
                    start: n.note.onset_s,
                    end: n.note.offset_s,
                    direction,
                    attack_s,
                    beta,
                });
            } else if let Some(s) = strokes.last_mut() {
                s.end = s.end.max(n.note.offset_s);
            }
            let glide_from = if new_stroke {
                None
            } else {
                plans.last().map(|p| p.period)
            };
            plans.push(NotePlan {
                onset: n.note.onset_s,
                offset: n.note.offset_s,
                period,
                glide_from,
                glide_s,
                vibrato: (!open).then_some(vib),
                dynamic: f64::from(n.dynamic).clamp(0.0, 1.0),
                accent: n.accent,
                stroke: strokes.len() - 1,
            });
        }
        (plans, strokes)
    }
}

impl Renderer for WaveguideViolin {
    fn name(&self) -> &'static str {
        "waveguide"
    }

    fn render(
        &self,
        timeline: &Timeline,
        settings: &RenderSettings,
    ) -> Result<Vec<f32>, RenderError> {
        settings.validate()?;
        if !(timeline.duration_s.is_finite() && timeline.duration_s >= 0.0) {
            return Err(RenderError::Settings(format!(
                "timeline duration {} s is not a finite non-negative number",
                timeline.duration_s
            )));
        }
        let cfg = &self.config;
        let sr = f64::from(settings.sample_rate_hz);
        let n_samples = (timeline.duration_s * sr).ceil() as usize;
        let root = Rng::new(settings.seed);
        let mut r = root.fork(1);
        let item = ItemDraw {
            beta: r.uniform(cfg.beta.0, cfg.beta.1),
            force: r.uniform(cfg.force.0, cfg.force.1),
            noise: r.uniform(cfg.bow_noise.0, cfg.bow_noise.1),
            lp_a: r.uniform(0.15, 0.45),
            string_t60: r.uniform(cfg.string_t60_s.0, cfg.string_t60_s.1),
            damp_t60: r.uniform(cfg.damp_t60_s.0, cfg.damp_t60_s.1),
            velocity_scale: r.uniform(0.85, 1.15),
        };
        let mut jitter = |f: f64, g: f64| {
            (
                f * r.uniform(0.92, 1.08),
                g + r.uniform(-1.5, 1.5),
                r.uniform(0.8, 1.25),
            )
        };
        // Body: air mode, main wood modes, the bridge hill, the upper roll-off.
        let modes = [
            (jitter(280.0, 8.0), 2.5),
            (jitter(450.0, 6.0), 3.0),
            (jitter(1_000.0, -3.0), 1.5),
            (jitter(2_600.0, 7.0), 1.2),
            (jitter(6_000.0, -9.0), 0.7),
        ];
        let mut body: Vec<Biquad> = modes
            .iter()
            .map(|&((f, g, qs), q)| Biquad::peaking(sr, f, g, q * qs))
            .collect();
        let tune = 2f64.powf(settings.tuning_cents / 1200.0);
        let (plans, strokes) = self.plan(&timeline.notes, sr, tune, &item, &root);
        let max_period = plans
            .iter()
            .map(|p| p.period * 2f64.powf(40.0 / 1200.0))
            .fold(16.0, f64::max);
        let mut string = BowedString::new(max_period, item.lp_a);
        let mut noise_rng = root.fork(2);
        let noise_lp = 1.0 - (-std::f64::consts::TAU * 800.0 / sr).exp();
        let dc_coeff = (-std::f64::consts::TAU * 30.0 / sr).exp();
        let mut state = RunState::default();
        let mut out = Vec::with_capacity(n_samples);
        let dt = 1.0 / sr;
        let mut note_idx = 0usize;
        for i in 0..n_samples {
            let t = i as f64 * dt;
            while note_idx + 1 < plans.len() && t >= plans[note_idx + 1].onset {
                note_idx += 1;
            }
            let Some(note) = plans.get(note_idx) else {
                out.push(0.0);
                continue;
            };
            let stroke = &strokes[note.stroke];
            let bow = bow_at(t, note, stroke, &item);
            // Bow noise: low-passed white noise modulating the velocity.
            state.noise += noise_lp * (noise_rng.uniform(-1.0, 1.0) - state.noise);
            let on_string = bow.is_some();
            let (velocity, force) = bow.unwrap_or((0.0, 0.0));
            let velocity = velocity * item.velocity_scale * (1.0 + 3.0 * item.noise * state.noise);
            let period = period_at(t, note);
            let t60 = if on_string || t < note.offset {
                item.string_t60
            } else {
                item.damp_t60
            };
            let f0 = sr / period;
            let input = BowInput {
                period,
                beta: stroke.beta,
                velocity: stroke.direction * velocity,
                force,
                on_string,
                loop_gain: 10f64.powf(-3.0 / (f0 * t60)),
            };
            let y = string.tick(&input);
            // DC blocker, then the body.
            let hp = y - state.dc_x + dc_coeff * state.dc_y;
            state.dc_x = y;
            state.dc_y = hp;
            let v = body.iter_mut().fold(hp, |v, f| f.process(v));
            out.push((v * cfg.output_gain) as f32);
        }
        Ok(out)
    }
}

#[derive(Debug, Default)]
struct RunState {
    noise: f64,
    dc_x: f64,
    dc_y: f64,
}

/// Bow velocity magnitude and force at `t`, or `None` when the hair is off the string.
fn bow_at(t: f64, note: &NotePlan, stroke: &StrokePlan, item: &ItemDraw) -> Option<(f64, f64)> {
    if t < stroke.start || t > stroke.end {
        return None;
    }
    let since = t - stroke.start;
    let attack = 1.0 - (-3.0 * since / stroke.attack_s).exp();
    // Deceleration to rest over the stroke's last 10–25 ms (a reversal, or the stop before
    // a rest).
    let decel_s = (0.3 * (stroke.end - stroke.start)).clamp(0.005, 0.025);
    let release = smoothstep((stroke.end - t) / decel_s);
    let dyn_v = 0.04 + 0.22 * note.dynamic.powf(1.2);
    let dyn_f = item.force * (0.55 + 0.45 * note.dynamic);
    let accent = if note.accent {
        1.0 + 0.6 * (-(t - note.onset).max(0.0) / 0.05).exp()
    } else {
        1.0
    };
    Some((dyn_v * attack * release * accent, dyn_f * accent))
}

/// Loop period (samples) at `t`: glide from a slurred predecessor, then vibrato.
fn period_at(t: f64, note: &NotePlan) -> f64 {
    let since = t - note.onset;
    let mut period = note.period;
    if let Some(from) = note.glide_from {
        if since < note.glide_s {
            let s = smoothstep(since / note.glide_s);
            period = from * (note.period / from).powf(s);
        }
    }
    if let Some((depth, rate, delay, phase)) = note.vibrato {
        if since > delay {
            let ramp = ((since - delay) / 0.25).min(1.0);
            let cents =
                ramp * depth * (std::f64::consts::TAU * rate * (since - delay) + phase).sin();
            period *= 2f64.powf(-cents / 1200.0);
        }
    }
    period
}

#[cfg(test)]
#[path = "waveguide_tests.rs"]
mod tests;
