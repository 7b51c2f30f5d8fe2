//! From beats to seconds: gentle rubato, articulation, and the exact labels (bow changes,
//! beats, downbeats, an arousal proxy) that the corpus ships.

use serde::{Deserialize, Serialize};

use crate::score::Etude;
use net_core::rng::Rng;

/// A note as played, in seconds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TimedNote {
    /// Onset in seconds.
    pub onset_s: f64,
    /// End of the sound in seconds (before the release tail).
    pub offset_s: f64,
    /// MIDI pitch.
    pub midi: u8,
    /// The note starts a new bow stroke (a bow change, or the first stroke after a rest).
    pub bow_change: bool,
    /// Dynamic level 0..=1.
    pub dynamic: f32,
    /// Accented attack.
    pub accent: bool,
    /// Where the note is played (filled by [`Timeline::assign_fingering`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fingering: Option<fingering::Fingering>,
}

/// The played étude with every label the corpus writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Timeline {
    /// Total length in seconds (the last bar line plus a short tail).
    pub duration_s: f64,
    /// Notes in time order.
    pub notes: Vec<TimedNote>,
    /// Every beat, in seconds.
    pub beats_s: Vec<f64>,
    /// Every downbeat (first beat of each bar), in seconds.
    pub downbeats_s: Vec<f64>,
    /// Arousal proxy at 2 Hz in [-1, 1] (see [`arousal_proxy`]).
    pub arousal_2hz: Vec<f32>,
    /// Nominal tempo in bpm.
    pub tempo_bpm: f64,
}

impl Timeline {
    /// Plans every note's fingering with `planner` (a note it cannot play keeps `None`).
    pub fn assign_fingering(&mut self, planner: &dyn fingering::FingeringPlanner) {
        let midi: Vec<u8> = self.notes.iter().map(|n| n.midi).collect();
        if let Ok(plan) = planner.plan(&midi) {
            for (n, f) in self.notes.iter_mut().zip(plan) {
                n.fingering = Some(f);
            }
        }
    }

    /// Onsets of the notes that start a bow stroke.
    pub fn bow_changes_s(&self) -> Vec<f64> {
        self.notes
            .iter()
            .filter(|n| n.bow_change)
            .map(|n| n.onset_s)
            .collect()
    }
}

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
                onset_s,
                offset_s: end_s - gap,
                midi: n.midi,
                bow_change: !n.slurred_from_previous,
                dynamic: n.dynamic,
                accent: n.accent,
                fingering: None,
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

/// The arousal proxy at 2 Hz, in [-1, 1]: a documented stand-in for a listener's arousal
/// built from the correlates music-emotion research reports for it — loudness and event
/// density (Gabrielsson & Lindström 2010; Eerola & Vuoskoski 2013) — as far as they can be
/// heard in each half second:
///
/// `a(k) = tanh(1.8·(d̄(k) − 0.45) + 0.5·(ρ(k) − 3)/3)`
///
/// where `d̄` is the mean over the half second `[0.5k, 0.5k + 0.5)` of the dynamic of the
/// sounding note (0 where nothing sounds) and `ρ` the note onsets per second in the 2 s
/// around its centre; then smoothed with a [1, 2, 1]/4 kernel so it moves like DEAM's
/// annotations. (Version 1 sampled the dynamic at the frame's centre — a 30 ms gap between
/// détaché notes then read as silence — and added `0.9·(tempo − 110)/60` from the score's
/// bpm, which half-second frames cannot show: the speed they can hear is the event rate
/// `ρ`. See emotion-net's README.)
pub fn arousal_proxy(notes: &[TimedNote], duration_s: f64) -> Vec<f32> {
    let spans: Vec<(f64, f64, f32)> = notes
        .iter()
        .map(|n| (n.onset_s, n.offset_s, n.dynamic))
        .collect();
    arousal_proxy_of_spans(&spans, duration_s)
}

/// [`arousal_proxy`] of sounding spans `(onset_s, offset_s, dynamic 0..=1)` in onset order
/// (e.g. a `Performance`'s notes and dynamics).
///
/// ```
/// // 4 s of quarter notes at 120 bpm, forte, then 2 s of silence.
/// let spans: Vec<(f64, f64, f32)> = (0..8).map(|i| (i as f64 * 0.5, i as f64 * 0.5 + 0.45, 0.8)).collect();
/// let a = corpus::timing::arousal_proxy_of_spans(&spans, 6.0);
/// assert_eq!(a.len(), 12);
/// assert!(a[3] > 0.3 && a[11] < -0.5);
/// ```
pub fn arousal_proxy_of_spans(spans: &[(f64, f64, f32)], duration_s: f64) -> Vec<f32> {
    const SAMPLES_PER_FRAME: usize = 50;
    let n = (duration_s * 2.0).ceil() as usize;
    if n == 0 {
        return Vec::new();
    }
    // The louder sounding level every 10 ms (0 in silence).
    let mut level = vec![0.0f64; n * SAMPLES_PER_FRAME];
    let per_s = 2.0 * SAMPLES_PER_FRAME as f64;
    for &(on, off, dynamic) in spans {
        let first = (on * per_s).ceil().max(0.0) as usize;
        let last = ((off * per_s).ceil().max(0.0) as usize).min(level.len());
        for v in level.iter_mut().take(last).skip(first) {
            *v = v.max(f64::from(dynamic));
        }
    }
    let onsets: Vec<f64> = spans.iter().map(|s| s.0).collect();
    let raw: Vec<f64> = (0..n)
        .map(|k| {
            let frame = &level[k * SAMPLES_PER_FRAME..(k + 1) * SAMPLES_PER_FRAME];
            let d = frame.iter().sum::<f64>() / SAMPLES_PER_FRAME as f64;
            let t = k as f64 * 0.5 + 0.25;
            let density = onsets.iter().filter(|&&o| (o - t).abs() <= 1.0).count() as f64 / 2.0;
            (1.8 * (d - 0.45) + 0.5 * (density - 3.0) / 3.0).tanh()
        })
        .collect();
    (0..n)
        .map(|k| {
            let a = raw[k.saturating_sub(1)];
            let b = raw[k];
            let c = raw[(k + 1).min(n - 1)];
            ((a + 2.0 * b + c) / 4.0) as f32
        })
        .collect()
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
                assert!(n.offset_s > n.onset_s && n.offset_s <= t.duration_s);
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
