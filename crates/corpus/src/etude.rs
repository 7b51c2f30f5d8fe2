//! Procedural études: seeded scales, arpeggios, walks, sequences and repeated notes in
//! varied meters, rhythms, articulations and dynamics.

use serde::{Deserialize, Serialize};

use crate::score::{Etude, Meter, ScoreNote};
use net_core::rng::Rng;

/// Lowest pitch (open G string).
pub const LOWEST_MIDI: u8 = 55;
/// Highest pitch the generator may use (E7).
pub const HIGHEST_MIDI: u8 = 100;
/// Upper end of the usual range (E6): notes above it are rare.
pub const USUAL_TOP_MIDI: u8 = 88;

/// What the generator may produce.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EtudeConfig {
    /// Target length in seconds (bars are added until it is reached).
    pub target_s: f64,
    /// Tempo range in bpm.
    pub tempo_bpm: (f64, f64),
    /// Probability that a phrase is played legato (slurs of 2–8 notes) rather than détaché.
    pub legato_share: f64,
    /// Probability of a rest at a phrase end.
    pub rest_share: f64,
    /// Probability that a phrase goes above E6.
    pub high_phrase_share: f64,
}

impl Default for EtudeConfig {
    fn default() -> Self {
        Self {
            target_s: 30.0,
            tempo_bpm: (50.0, 170.0),
            legato_share: 0.5,
            rest_share: 0.35,
            high_phrase_share: 0.08,
        }
    }
}

const MODES: [(&str, [u8; 7]); 5] = [
    ("major", [0, 2, 4, 5, 7, 9, 11]),
    ("minor", [0, 2, 3, 5, 7, 8, 10]),
    ("harmonic minor", [0, 2, 3, 5, 7, 8, 11]),
    ("dorian", [0, 2, 3, 5, 7, 9, 10]),
    ("mixolydian", [0, 2, 4, 5, 7, 9, 10]),
];

/// The kinds of melodic material.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Figure {
    Scale,
    Arpeggio,
    Walk,
    Sequence,
    Repeated,
}

/// Generates one étude from `seed`.
///
/// ```
/// use corpus::etude::{generate, EtudeConfig};
/// let e = generate(3, &EtudeConfig::default());
/// assert!(!e.notes.is_empty());
/// assert_eq!(e, generate(3, &EtudeConfig::default()));
/// ```
pub fn generate(seed: u64, cfg: &EtudeConfig) -> Etude {
    let mut rng = Rng::new(seed);
    let meter = *rng.pick(&Meter::ALL).unwrap_or(&Meter::FourFour);
    let (lo, hi) = cfg.tempo_bpm;
    // Log-uniform tempo: as many slow as fast pieces per octave of tempo.
    let tempo_bpm =
        (lo.max(1.0).ln() + rng.unit() * (hi.max(lo + 1.0).ln() - lo.max(1.0).ln())).exp();
    let tonic = rng.int(0, 11) as u8;
    let (mode_name, mode) = *rng.pick(&MODES).unwrap_or(&MODES[0]);
    let scale = scale_pitches(tonic, &mode);
    let bpb = meter.beats_per_bar();
    let beat_s = 60.0 / tempo_bpm;
    let bars = ((cfg.target_s / (beat_s * f64::from(bpb))).ceil() as u32).max(2);

    let mut notes: Vec<ScoreNote> = Vec::new();
    let mut bar = 0u32;
    // Start somewhere comfortable: around the D and A strings.
    let mut degree = nearest_degree(&scale, rng.int(62, 76) as u8);
    let mut level = rng.uniform(0.2, 0.9) as f32;
    while bar < bars {
        let phrase_bars = (rng.int(1, 4) as u32).min(bars - bar);
        let legato = rng.chance(cfg.legato_share);
        let high = rng.chance(cfg.high_phrase_share);
        let figure = *rng
            .pick(&[
                Figure::Scale,
                Figure::Arpeggio,
                Figure::Walk,
                Figure::Sequence,
                Figure::Repeated,
            ])
            .unwrap_or(&Figure::Walk);
        let target_level = rng.uniform(0.1, 1.0) as f32;
        let rest_at_end = rng.chance(cfg.rest_share);
        let mut onsets = Vec::new();
        for b in 0..phrase_bars {
            for (start, dur) in bar_rhythm(&mut rng, meter) {
                onsets.push((f64::from((bar + b) * bpb) + start, dur));
            }
        }
        if rest_at_end && onsets.len() > 2 {
            // Replace the phrase's last note by a rest.
            onsets.pop();
        }
        let top = if high { HIGHEST_MIDI } else { USUAL_TOP_MIDI };
        let pitches = figure_pitches(&mut rng, figure, &scale, &mut degree, onsets.len(), top);
        let mut slur_left = 0u32;
        let n = onsets.len().max(1);
        for (i, ((start, dur), midi)) in onsets.iter().zip(pitches).enumerate() {
            let t = i as f32 / n as f32;
            let dynamic = (level + (target_level - level) * t).clamp(0.0, 1.0);
            let prev_end = notes.last().map(ScoreNote::end_beats);
            let touching = prev_end.is_some_and(|e| (e - start).abs() < 1e-9);
            let slurred = legato && slur_left > 0 && touching;
            if slurred {
                slur_left -= 1;
            } else {
                slur_left = if legato { rng.int(1, 7) as u32 } else { 0 };
            }
            let on_downbeat =
                (start - (start / f64::from(bpb)).floor() * f64::from(bpb)).abs() < 1e-9;
            notes.push(ScoreNote {
                start_beats: *start,
                dur_beats: *dur,
                midi,
                slurred_from_previous: slurred,
                dynamic,
                accent: !slurred && on_downbeat && rng.chance(0.3),
            });
        }
        level = target_level;
        bar += phrase_bars;
    }
    Etude {
        meter,
        tempo_bpm,
        tonic,
        mode: mode_name.to_string(),
        bars,
        notes,
    }
}

/// Every pitch of the mode from G3 to E7.
fn scale_pitches(tonic: u8, mode: &[u8; 7]) -> Vec<u8> {
    (LOWEST_MIDI..=HIGHEST_MIDI)
        .filter(|m| mode.contains(&((m + 12 - tonic % 12) % 12)))
        .collect()
}

fn nearest_degree(scale: &[u8], midi: u8) -> usize {
    scale
        .iter()
        .enumerate()
        .min_by_key(|(_, &m)| (i32::from(m) - i32::from(midi)).abs())
        .map_or(0, |(i, _)| i)
}

/// One bar's rhythm as (start within the bar, duration) in beats.
fn bar_rhythm(rng: &mut Rng, meter: Meter) -> Vec<(f64, f64)> {
    let bpb = f64::from(meter.beats_per_bar());
    let patterns: &[&[f64]] = match meter {
        Meter::SixEight => &[
            &[1.0, 1.0],
            &[2.0],
            &[1.0 / 3.0; 6],
            &[2.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0, 1.0 / 3.0],
            &[1.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
            &[0.5, 1.0 / 6.0, 1.0 / 3.0, 1.0],
            &[1.0 / 6.0; 12],
        ],
        _ => &[
            &[1.0],
            &[0.5, 0.5],
            &[0.25; 4],
            &[0.75, 0.25],
            &[1.0 / 3.0; 3],
            &[2.0],
            &[1.5, 0.5],
            &[0.5, 0.25, 0.25],
            &[4.0],
        ],
    };
    let mut out = Vec::new();
    let mut pos = 0.0;
    let mut guard = 0;
    while pos < bpb - 1e-9 && guard < 64 {
        guard += 1;
        let fits: Vec<&&[f64]> = patterns
            .iter()
            .filter(|p| pos + p.iter().sum::<f64>() <= bpb + 1e-9)
            .collect();
        let Some(p) = rng.pick(&fits) else { break };
        for d in p.iter() {
            out.push((pos, *d));
            pos += d;
        }
    }
    out
}

fn figure_pitches(
    rng: &mut Rng,
    figure: Figure,
    scale: &[u8],
    degree: &mut usize,
    count: usize,
    top: u8,
) -> Vec<u8> {
    let top_degree = scale.iter().rposition(|&m| m <= top).unwrap_or(0);
    let clamp = |d: i64| d.clamp(0, top_degree as i64) as usize;
    let mut out = Vec::with_capacity(count);
    let mut dir: i64 = if rng.chance(0.5) { 1 } else { -1 };
    let mut d = *degree as i64;
    let seq_pattern = [0i64, 2, 1, 3];
    let mut seq_base = d;
    for i in 0..count {
        match figure {
            Figure::Scale => d += dir,
            Figure::Arpeggio => d += 2 * dir,
            Figure::Walk => d += rng.int(-3, 3),
            Figure::Repeated => {
                if i % 4 == 0 && i > 0 {
                    d += rng.int(-2, 2);
                }
            }
            Figure::Sequence => {
                if i % 4 == 0 && i > 0 {
                    seq_base += dir;
                }
                d = seq_base + seq_pattern[i % 4] * dir.signum();
            }
        }
        if d <= 0 || d >= top_degree as i64 {
            dir = -dir;
            seq_base = clamp(seq_base) as i64;
        }
        d = clamp(d) as i64;
        out.push(scale.get(d as usize).copied().unwrap_or(LOWEST_MIDI));
    }
    *degree = clamp(d);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn etudes_are_valid_and_varied() {
        let mut meters = std::collections::HashSet::new();
        for seed in 0..200 {
            let e = generate(seed, &EtudeConfig::default());
            meters.insert(e.meter.name());
            assert!(e.tempo_bpm >= 50.0 && e.tempo_bpm <= 170.0);
            let mut prev_end = 0.0;
            for n in &e.notes {
                assert!(n.start_beats + 1e-9 >= prev_end, "overlap in seed {seed}");
                assert!(n.dur_beats > 0.0);
                assert!((LOWEST_MIDI..=HIGHEST_MIDI).contains(&n.midi));
                assert!((0.0..=1.0).contains(&n.dynamic));
                prev_end = n.end_beats();
            }
            assert!(prev_end <= e.total_beats() + 1e-9);
            assert!(!e.notes[0].slurred_from_previous);
        }
        assert_eq!(meters.len(), 4);
    }

    #[test]
    fn slurs_never_cross_rests() {
        for seed in 0..100 {
            let e = generate(seed, &EtudeConfig::default());
            for w in e.notes.windows(2) {
                if w[1].slurred_from_previous {
                    assert!((w[0].end_beats() - w[1].start_beats).abs() < 1e-9);
                }
            }
        }
    }
}
