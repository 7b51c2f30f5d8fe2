//! The synthetic score: beats with rubato, a rhythm per bar, a melody over a chord per bar,
//! articulations (slurs, repeats, rests) and accents.

use super::piece::{Rng, SynthConfig};

/// One event of the score: a note or a rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    /// Start in seconds.
    pub onset_s: f64,
    /// End of the written duration (the next event's start) in seconds.
    pub end_s: f64,
    /// MIDI pitch, `None` for a rest.
    pub midi: Option<u8>,
    /// Joined to the previous note without a re-attack.
    pub slurred: bool,
    /// Level relative to the piece's base level, in dB.
    pub level_db: f64,
    /// Starts on the first beat of a bar.
    pub on_downbeat: bool,
}

/// A composed piece before rendering.
#[derive(Debug, Clone, PartialEq)]
pub struct Score {
    /// Events in time order, back to back.
    pub events: Vec<Event>,
    /// Every beat time in seconds.
    pub beats_s: Vec<f64>,
    /// Downbeat times in seconds.
    pub downbeats_s: Vec<f64>,
    /// When the last event ends.
    pub end_s: f64,
}

/// Major scale steps.
const MAJOR: [u8; 7] = [0, 2, 4, 5, 7, 9, 11];
/// Lowest and highest pitch used (open G to E6).
const MIDI_RANGE: (i32, i32) = (55, 88);

/// Composes the score of `cfg`.
pub fn compose(cfg: &SynthConfig) -> Score {
    let mut rng = Rng::new(cfg.seed);
    let bpb = usize::from(cfg.time_signature.beats_per_bar.max(1));
    let n_beats = cfg.bars.max(1) * bpb;
    // Beat grid with a smooth rubato curve (one cycle every four bars).
    let phase0 = rng.uniform(0.0, std::f64::consts::TAU);
    let mut grid = Vec::with_capacity(n_beats + 1);
    let mut t = cfg.padding_s;
    for k in 0..=n_beats {
        grid.push(t);
        let swing =
            1.0 + cfg.rubato * (std::f64::consts::TAU * k as f64 / (4 * bpb) as f64 + phase0).sin();
        t += 60.0 / (cfg.tempo_bpm * swing);
    }
    let at = |beat: f64| -> f64 {
        let k = (beat.floor() as usize).min(n_beats - 1);
        grid[k] + (beat - k as f64) * (grid[k + 1] - grid[k])
    };
    let beat_s = 60.0 / cfg.tempo_bpm;
    let compound = cfg.time_signature.subdivisions == 3;

    // Rhythm: (start beat, length in beats, on downbeat).
    let mut rhythm: Vec<(f64, f64, bool)> = Vec::new();
    for bar in 0..cfg.bars.max(1) {
        let mut j = 0usize;
        while j < bpb {
            let beat = (bar * bpb + j) as f64;
            let long_p = if j == 0 { 0.45 } else { 0.2 };
            if j + 1 < bpb && j.is_multiple_of(2) && rng.chance(long_p) {
                rhythm.push((beat, 2.0, j == 0));
                j += 2;
                continue;
            }
            let cell: &[f64] = if compound {
                match rng.below(3) {
                    0 => &[1.0],
                    1 => &[1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
                    _ => &[2.0 / 3.0, 1.0 / 3.0],
                }
            } else {
                let r = rng.unit();
                if r < 0.35 {
                    &[1.0]
                } else if r < 0.75 || beat_s * 0.25 < 0.12 {
                    &[0.5, 0.5]
                } else if r < 0.85 || beat_s * 0.25 < 0.14 {
                    &[0.75, 0.25]
                } else {
                    &[0.25, 0.25, 0.25, 0.25]
                }
            };
            let mut x = beat;
            for (c, len) in cell.iter().enumerate() {
                rhythm.push((x, *len, j == 0 && c == 0));
                x += len;
            }
            j += 1;
        }
    }

    // Melody.
    let tonic = [55i32, 60, 62, 57, 65, 58][rng.below(6)];
    let to_midi =
        |s: i32| tonic + 12 * s.div_euclid(7) + i32::from(MAJOR[s.rem_euclid(7) as usize]);
    let lowest = (0..40).find(|&s| to_midi(s) >= MIDI_RANGE.0).unwrap_or(0);
    let highest = (0..60)
        .rev()
        .find(|&s| to_midi(s) <= MIDI_RANGE.1)
        .unwrap_or(lowest + 14);
    let mut degree = lowest + 7 + rng.below(5) as i32;
    let mut events: Vec<Event> = Vec::with_capacity(rhythm.len());
    let last_bar = cfg.bars.max(1) - 1;
    for (start, len, on_downbeat) in rhythm {
        let bar = (start / bpb as f64).floor() as usize;
        let is_beat = (start - start.round()).abs() < 1e-9;
        if on_downbeat {
            let chord_root = if bar == 0 || bar == last_bar {
                0
            } else {
                [0, 3, 4, 5][rng.below(4)]
            };
            // Nearest chord tone at least a step away: a pitch change at the bar line.
            let tones = [chord_root, chord_root + 2, chord_root + 4];
            let mut best = degree;
            let mut best_dist = i32::MAX;
            for base in (degree - 7)..=(degree + 7) {
                let d = (base - degree).abs();
                if tones.iter().any(|t| (base - t).rem_euclid(7) == 0) && d > 0 && d < best_dist {
                    best = base;
                    best_dist = d;
                }
            }
            degree = best;
        } else if !rng.chance(cfg.repeat_prob) {
            let step = match rng.below(10) {
                0..=2 => 1,
                3..=5 => -1,
                6 => 2,
                7 => -2,
                8 => 3 + rng.below(2) as i32,
                _ => -3 - rng.below(2) as i32,
            };
            degree += step;
        }
        if degree < lowest {
            degree = lowest + (lowest - degree);
        }
        if degree > highest {
            degree = highest - (degree - highest);
        }
        degree = degree.clamp(lowest, highest);
        let rest = !on_downbeat
            && events.last().is_some_and(|e| e.midi.is_some())
            && rng.chance(cfg.rest_prob);
        let midi = (!rest).then(|| to_midi(degree).clamp(0, 127) as u8);
        let slurred = match (events.last(), midi) {
            (Some(prev), Some(m)) => {
                !on_downbeat && prev.midi.is_some_and(|p| p != m) && rng.chance(cfg.slur_prob)
            }
            _ => false,
        };
        let accent = if on_downbeat {
            cfg.downbeat_accent_db
        } else if is_beat {
            1.0
        } else {
            0.0
        };
        events.push(Event {
            onset_s: at(start),
            end_s: at(start + len),
            midi,
            slurred,
            level_db: accent + rng.uniform(-1.0, 1.0),
            on_downbeat,
        });
    }
    let downbeats_s = (0..cfg.bars.max(1)).map(|b| grid[b * bpb]).collect();
    Score {
        end_s: grid[n_beats],
        beats_s: grid[..n_beats].to_vec(),
        downbeats_s,
        events,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::TimeSignature;

    #[test]
    fn events_tile_the_bars_and_stay_in_range() {
        for seed in 0..20 {
            let cfg = SynthConfig::varied(seed, 20.0);
            let s = compose(&cfg);
            assert_eq!(
                s.beats_s.len(),
                cfg.bars * usize::from(cfg.time_signature.beats_per_bar)
            );
            for w in s.events.windows(2) {
                assert!((w[0].end_s - w[1].onset_s).abs() < 1e-9);
            }
            for e in &s.events {
                assert!(e.end_s - e.onset_s > 0.09, "{e:?}");
                if let Some(m) = e.midi {
                    assert!((55..=88).contains(&m));
                }
            }
            assert!(s.events.iter().all(|e| !(e.slurred && e.on_downbeat)));
        }
        let c = SynthConfig {
            time_signature: TimeSignature::SIX_EIGHT,
            ..SynthConfig::default()
        };
        assert_eq!(compose(&c).downbeats_s.len(), c.bars);
    }
}
