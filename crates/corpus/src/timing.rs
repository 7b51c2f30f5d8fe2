//! From beats to seconds: gentle rubato, articulation, and the exact labels (bow changes,
//! beats, downbeats, an arousal proxy) that the corpus ships.

use performance::{arousal_proxy, Note, TimedNote, Timeline};

use crate::score::Etude;
use net_core::rng::Rng;

/// Rubato: the tempo factor is `1 + depth · sin(2π · beat / period + phase)`, with depth up to
/// 5 % and a period of 8–24 beats, so tempo breathes over phrases without jumping.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Rubato {
    depth: f64,
    period_beats: f64,
    phase: f64,
}

impl Rubato {
    fn factor(&self, beat: f64) -> f64 {
        1.0 + self.depth
            * (2.0 * std::f64::consts::PI * beat / self.period_beats + self.phase).sin()
    }
}

/// Seconds of silence after the last bar.
const TAIL_S: f64 = 0.6;

/// Plays `etude`: seeded rubato, détaché notes slightly detached (92 % of their length),
/// slurred notes joined, phrase ends before rests released a little early.
pub fn play(etude: &Etude, seed: u64) -> Timeline {
    let mut rng = Rng::new(seed);
    let rubato = Rubato {
        depth: rng.uniform(0.0, 0.05),
        period_beats: rng.uniform(8.0, 24.0),
        phase: rng.uniform(0.0, std::f64::consts::TAU),
    };
    let total_beats = etude.total_beats();
    let clock = BeatClock::new(etude.tempo_bpm, rubato, total_beats);
    let notes: Vec<TimedNote> = etude
        .notes
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let next = etude.notes.get(i + 1);
            let legato_into_next = next.is_some_and(|m| m.slurred_from_previous);
            let touching_next = next.is_some_and(|m| (m.start_beats - n.end_beats()).abs() < 1e-9);
            let onset_s = clock.seconds(n.start_beats);
            let end_s = clock.seconds(n.end_beats());
            let gap = if legato_into_next {
                0.0
            } else if touching_next {
                // A bow change: the old stroke stops just before the new one.
                0.03f64.min(0.08 * (end_s - onset_s))
            } else {
                0.1 * (end_s - onset_s)
            };
            TimedNote {
                note: Note::new(onset_s, end_s - gap, n.midi),
                bow_change: !n.slurred_from_previous,
                dynamic: n.dynamic,
                accent: n.accent,
            }
        })
        .collect();
    let bpb = etude.meter.beats_per_bar() as usize;
    let beats_s: Vec<f64> = (0..total_beats as usize)
        .map(|b| clock.seconds(b as f64))
        .collect();
    let downbeats_s: Vec<f64> = beats_s.iter().step_by(bpb).copied().collect();
    let duration_s = clock.seconds(total_beats) + TAIL_S;
    let arousal_2hz = arousal_proxy(&notes, duration_s);
    Timeline {
        duration_s,
        notes,
        beats_s,
        downbeats_s,
        arousal_2hz,
        tempo_bpm: etude.tempo_bpm,
    }
}

/// Beat position → seconds by integrating the rubato tempo curve.
struct BeatClock {
    /// Seconds at each 1/48 beat.
    table: Vec<f64>,
}

const STEPS_PER_BEAT: f64 = 48.0;

impl BeatClock {
    fn new(tempo_bpm: f64, rubato: Rubato, total_beats: f64) -> Self {
        let n = (total_beats * STEPS_PER_BEAT).ceil() as usize + 2;
        let mut table = Vec::with_capacity(n);
        let mut t = 0.0;
        for i in 0..n {
            table.push(t);
            let mid = (i as f64 + 0.5) / STEPS_PER_BEAT;
            t += 60.0 / (tempo_bpm * rubato.factor(mid)) / STEPS_PER_BEAT;
        }
        Self { table }
    }

    fn seconds(&self, beat: f64) -> f64 {
        let x = (beat * STEPS_PER_BEAT).max(0.0);
        let i = (x.floor() as usize).min(self.table.len().saturating_sub(2));
        let frac = x - i as f64;
        self.table[i] + frac * (self.table[i + 1] - self.table[i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::etude::{generate, EtudeConfig};

    #[test]
    fn labels_are_consistent() {
        for seed in 0..50 {
            let e = generate(seed, &EtudeConfig::default());
            let t = play(&e, seed);
            assert!(t.beats_s.windows(2).all(|w| w[1] > w[0]));
            assert_eq!(t.downbeats_s.len() as u32, e.bars);
            for (n, s) in t.notes.iter().zip(&e.notes) {
                assert!(n.note.offset_s > n.note.onset_s && n.note.offset_s <= t.duration_s);
                assert_eq!(n.bow_change, !s.slurred_from_previous);
            }
            assert!(t.arousal_2hz.iter().all(|a| (-1.0..=1.0).contains(a)));
            assert_eq!(t.arousal_2hz.len(), (t.duration_s * 2.0).ceil() as usize);
            // Rubato is gentle: every beat within 6 % of the nominal beat length.
            let nominal = 60.0 / e.tempo_bpm;
            assert!(t
                .beats_s
                .windows(2)
                .all(|w| ((w[1] - w[0]) / nominal - 1.0).abs() < 0.06));
        }
    }

    #[test]
    fn bow_changes_differ_from_onsets_when_slurred() {
        let mut fewer = 0;
        for seed in 0..30 {
            let t = play(&generate(seed, &EtudeConfig::default()), 1);
            if t.bow_changes_s().len() < t.notes.len() {
                fewer += 1;
            }
        }
        assert!(fewer > 10);
    }
}
