//! Additive rendering of a [`Score`] into a labelled [`SynthPiece`].

use super::piece::{Rng, SynthConfig, SynthNote, SynthPiece};
use super::score::{compose, Score};
use crate::error::{PitchError, Result};

/// Attack time constant of a bowed note, in seconds.
const ATTACK_TAU_S: f64 = 0.025;
/// Length of the amplitude dip before a bow change, in seconds.
const BOW_CHANGE_DIP_S: f64 = 0.03;
/// Level at the bottom of that dip and at the start of a re-attack.
const BOW_CHANGE_FLOOR: f64 = 0.25;
/// Decay constant and length of the bow-noise burst at a bow change, in seconds.
const BURST_TAU_S: f64 = 0.015;
const BURST_S: f64 = 0.06;
/// Fade-out before a rest, in seconds.
const RELEASE_S: f64 = 0.04;
/// Highest harmonic frequency relative to the sample rate.
const HARMONIC_LIMIT: f64 = 0.45;
/// Samples between updates of the harmonic amplitudes.
const BLOCK: usize = 64;

/// Composes and renders `cfg`. Errors on a configuration that cannot be rendered (zero
/// sample rate, non-positive tempo, no bars, bad probability ranges).
pub fn render(cfg: &SynthConfig) -> Result<SynthPiece> {
    validate(cfg)?;
    let score = compose(cfg);
    Ok(render_score(cfg, &score))
}

fn validate(cfg: &SynthConfig) -> Result<()> {
    let bad = |m: &str| Err(PitchError::InvalidConfig(format!("synth: {m}")));
    if cfg.sample_rate_hz < 8000 {
        return bad("sample_rate_hz must be ≥ 8000");
    }
    if !(cfg.tempo_bpm.is_finite() && (20.0..=400.0).contains(&cfg.tempo_bpm)) {
        return bad("tempo_bpm must be between 20 and 400");
    }
    if cfg.bars == 0 || cfg.time_signature.beats_per_bar == 0 {
        return bad("bars and beats_per_bar must be ≥ 1");
    }
    if !matches!(cfg.time_signature.subdivisions, 2 | 3) {
        return bad("subdivisions must be 2 or 3");
    }
    if !(0.0..0.5).contains(&cfg.rubato) || cfg.padding_s.is_nan() || cfg.padding_s < 0.0 {
        return bad("rubato must be in [0, 0.5) and padding_s ≥ 0");
    }
    Ok(())
}

/// Renders a composed score.
pub fn render_score(cfg: &SynthConfig, score: &Score) -> SynthPiece {
    let sr = f64::from(cfg.sample_rate_hz);
    let mut rng = Rng::new(cfg.seed.wrapping_mul(0x2545_f491_4f6c_dd1d) ^ 0xa11ce);
    let n = ((score.end_s + cfg.padding_s) * sr).ceil() as usize;
    let idx = |t: f64| ((t * sr).round().max(0.0) as usize).min(n);
    let mut f0 = vec![0.0f64; n];
    let mut truth_f0 = vec![0.0f32; n];
    let mut amp = vec![0.0f32; n];
    let mut burst = vec![0.0f32; n];
    let mut notes = Vec::new();
    let events = &score.events;
    let mut prev_hz: Option<f64> = None;
    let mut prev_level = 0.0f64;
    for (i, ev) in events.iter().enumerate() {
        let Some(midi) = ev.midi else {
            prev_hz = None;
            continue;
        };
        let hz = 440.0 * ((f64::from(midi) - 69.0) / 12.0).exp2();
        let level = 10f64.powf(ev.level_db / 20.0);
        let next = events.get(i + 1);
        let legato = next.is_some_and(|e| e.midi.is_some());
        let next_reattacks = next.is_some_and(|e| e.midi.is_some() && !e.slurred);
        let duration = ev.end_s - ev.onset_s;
        let (sound_end, offset_s) = if legato {
            (ev.end_s, ev.end_s)
        } else {
            let stop = ev.end_s - (0.25 * duration).min(0.08);
            (stop, stop - RELEASE_S / 2.0)
        };
        let glide_s = rng.uniform(0.02, 0.05);
        let vib_depth = rng.uniform(cfg.vibrato_cents.0, cfg.vibrato_cents.1);
        let vib_rate = rng.uniform(cfg.vibrato_hz.0, cfg.vibrato_hz.1);
        let vib_delay = rng.uniform(0.12, 0.25);
        let start_level = if ev.slurred {
            prev_level
        } else if prev_hz.is_some() {
            BOW_CHANGE_FLOOR * level
        } else {
            0.0
        };
        for s in idx(ev.onset_s)..idx(sound_end) {
            let t = s as f64 / sr - ev.onset_s;
            // Pitch: glide from the previous note when slurred, then delayed vibrato.
            let mut pitch = hz;
            if let (true, Some(from)) = (ev.slurred, prev_hz) {
                if t < glide_s {
                    let w = 0.5 - 0.5 * (std::f64::consts::PI * t / glide_s).cos();
                    pitch = from * (hz / from).powf(w);
                }
            }
            if duration > 0.3 && t > vib_delay {
                let ramp = ((t - vib_delay) / 0.2).min(1.0);
                let cents =
                    vib_depth * ramp * (std::f64::consts::TAU * vib_rate * (t - vib_delay)).sin();
                pitch *= (cents / 1200.0).exp2();
            }
            f0[s] = pitch;
            // Level: attack (or crossfade when slurred), dip before a bow change, release.
            let mut a = if ev.slurred {
                level + (start_level - level) * (-t / 0.03).exp()
            } else {
                level + (start_level - level) * (-t / ATTACK_TAU_S).exp()
            };
            let to_end = ev.end_s - s as f64 / sr;
            if next_reattacks && to_end < BOW_CHANGE_DIP_S {
                a *= BOW_CHANGE_FLOOR + (1.0 - BOW_CHANGE_FLOOR) * to_end / BOW_CHANGE_DIP_S;
            }
            let to_stop = sound_end - s as f64 / sr;
            if !legato && to_stop < RELEASE_S {
                a *= to_stop / RELEASE_S;
            }
            amp[s] = a as f32;
            if !ev.slurred && t < BURST_S {
                burst[s] = (0.35 * level * (-t / BURST_TAU_S).exp()) as f32;
            }
            if s as f64 / sr < offset_s {
                truth_f0[s] = pitch as f32;
            }
        }
        notes.push(SynthNote {
            onset_s: ev.onset_s,
            offset_s,
            midi,
            slurred: ev.slurred,
        });
        prev_hz = legato.then_some(hz);
        prev_level = level;
    }
    let mut samples = additive(&f0, &amp, sr, &mut rng);
    add_noise(&mut samples, &burst, &amp, &mut rng);
    let peak = samples.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    if peak > 0.0 {
        let gain = 0.9 / peak;
        samples.iter_mut().for_each(|x| *x *= gain);
    }
    let floor = 0.9 * 10f64.powf(cfg.noise_floor_db / 20.0);
    for x in samples.iter_mut() {
        *x += (floor * rng.normal()) as f32;
    }
    SynthPiece {
        samples,
        sample_rate_hz: cfg.sample_rate_hz,
        notes,
        beats_s: score.beats_s.clone(),
        downbeats_s: score.downbeats_s.clone(),
        tempo_bpm: cfg.tempo_bpm,
        time_signature: cfg.time_signature,
        f0_hz: truth_f0,
    }
}

/// Relative level of a harmonic at `hz`: bowed-string 1/k slope shaped by body resonances
/// (around 450 Hz and the 2.8 kHz "bridge hill") and a roll-off above 6 kHz.
fn body_gain(hz: f64) -> f64 {
    let bump = |centre: f64, width: f64| (-((hz - centre) / width).powi(2)).exp();
    (1.0 + 0.8 * bump(450.0, 150.0) + 1.5 * bump(2800.0, 700.0)) / (1.0 + (hz / 6000.0).powi(2))
}

/// Harmonics of `f0` (continuous phase) weighted by `amp`, one complex rotation per
/// harmonic and sample.
fn additive(f0: &[f64], amp: &[f32], sr: f64, rng: &mut Rng) -> Vec<f32> {
    const MAX_HARMONICS: usize = 60;
    let phases: Vec<(f64, f64)> = (0..MAX_HARMONICS)
        .map(|_| {
            let p = rng.uniform(0.0, std::f64::consts::TAU);
            (p.cos(), p.sin())
        })
        .collect();
    let mut gains = vec![0.0f64; MAX_HARMONICS];
    let mut out = vec![0.0f32; f0.len()];
    let mut phase = 0.0f64;
    for (block_start, block) in f0.chunks(BLOCK).enumerate() {
        let start = block_start * BLOCK;
        let hz = block.iter().copied().fold(0.0, f64::max);
        let mut k_max = 0;
        if hz > 0.0 {
            for (k, g) in gains.iter_mut().enumerate() {
                let fk = hz * (k + 1) as f64;
                let limit = HARMONIC_LIMIT * sr;
                *g = if fk < limit {
                    k_max = k + 1;
                    body_gain(fk) / (k + 1) as f64 * (1.0 - fk / limit).min(0.2) * 5.0
                } else {
                    0.0
                };
            }
        }
        for (j, &f) in block.iter().enumerate() {
            let s = start + j;
            phase = (phase + std::f64::consts::TAU * f / sr) % std::f64::consts::TAU;
            if amp[s] == 0.0 || f <= 0.0 {
                continue;
            }
            let (zr, zi) = (phase.cos(), phase.sin());
            let (mut pr, mut pi) = (zr, zi);
            let mut acc = 0.0f64;
            for k in 0..k_max {
                let (cr, ci) = phases[k];
                acc += gains[k] * (pr * ci + pi * cr);
                let r = pr * zr - pi * zi;
                pi = pr * zi + pi * zr;
                pr = r;
            }
            out[s] = (acc * f64::from(amp[s])) as f32;
        }
    }
    out
}

/// Bow-noise bursts (high-passed white noise) and a faint hiss that follows the level.
fn add_noise(samples: &mut [f32], burst: &[f32], amp: &[f32], rng: &mut Rng) {
    let mut last = 0.0f64;
    for ((x, b), a) in samples.iter_mut().zip(burst).zip(amp) {
        let w = rng.normal();
        let hp = w - 0.8 * last;
        last = w;
        *x += (hp * (f64::from(*b) * 1.5 + f64::from(*a) * 0.02)) as f32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rendering_is_deterministic_and_labelled() {
        let cfg = SynthConfig {
            bars: 2,
            ..SynthConfig::default()
        };
        let a = render(&cfg).unwrap();
        let b = render(&cfg).unwrap();
        assert_eq!(a.samples, b.samples);
        assert_eq!(a.f0_hz.len(), a.samples.len());
        assert!(a.samples.iter().all(|x| x.is_finite() && x.abs() <= 1.0));
        let voiced = a.f0_hz.iter().filter(|&&f| f > 0.0).count();
        assert!(voiced > a.samples.len() / 2);
        let c = render(&SynthConfig { seed: 2, ..cfg }).unwrap();
        assert_ne!(a.samples, c.samples);
    }

    #[test]
    fn bad_configs_are_errors() {
        let bad = SynthConfig {
            tempo_bpm: 0.0,
            ..SynthConfig::default()
        };
        assert!(render(&bad).is_err());
        let bad = SynthConfig {
            bars: 0,
            ..SynthConfig::default()
        };
        assert!(render(&bad).is_err());
    }
}
