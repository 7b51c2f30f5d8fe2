//! A human performance of a [`Score`]: a tempo curve (rubato, drift, phrase-end and final
//! ritardandi, fermatas), per-note timing noise, articulation and dynamics, and the exact
//! labels that come with it — notes, bow changes (the slur rule), beats at the notated
//! level, downbeats, the tempo per beat and bow strokes with their direction.

use performance::{
    arousal_proxy, bow_directions, BowStroke, Note, TimeSignature, TimedNote, Timeline,
};
use serde::{Deserialize, Serialize};

use crate::score::Score;
use net_core::rng::Rng;

/// Seconds of silence after the last bar.
const TAIL_S: f64 = 0.6;
/// Tempo-curve resolution: steps per quarter note.
const STEPS_PER_Q: f64 = 48.0;
/// Fastest note rate a drawn tempo may ask of the player, notes per second.
const MAX_NOTES_PER_S: f64 = 13.0;

/// How one performance was timed (drawn from the seed; written to the manifest).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TimingDraw {
    /// Base tempo in notated beats per minute.
    pub tempo_bpm: f64,
    /// Rubato depths of the slow (phrase) and fast (bar) tempo waves, as fractions.
    pub rubato_depth: [f64; 2],
    /// Tempo at the very end relative to the base (final ritardando).
    pub final_ritardando: f64,
    /// Standard deviation of the per-note onset noise, seconds.
    pub onset_noise_s: f64,
    /// How long fermatas are held, as a multiple of the written length.
    pub fermata_stretch: f64,
}

/// A performed score: the timeline (notes with articulation and every time label) plus
/// what the timeline does not carry.
#[derive(Debug, Clone, PartialEq)]
pub struct Played {
    /// Notes, bow changes, beats, downbeats, arousal and nominal tempo.
    pub timeline: Timeline,
    /// The main time signature.
    pub time_signature: TimeSignature,
    /// Local tempo at each beat (from that beat to the next), notated beats per minute.
    pub tempo_bpm_per_beat: Vec<f64>,
    /// The timing that was drawn.
    pub timing: TimingDraw,
}

struct TempoCurve {
    /// Seconds at each step of 1/48 quarter.
    table: Vec<f64>,
}

impl TempoCurve {
    fn seconds(&self, q: f64) -> f64 {
        let x = (q * STEPS_PER_Q).max(0.0);
        let last = self.table.len().saturating_sub(2);
        let i = (x.floor() as usize).min(last);
        let frac = (x - i as f64).min(1.0);
        match (self.table.get(i), self.table.get(i + 1)) {
            (Some(a), Some(b)) => a + frac * (b - a),
            _ => 0.0,
        }
    }
}

/// The 10th percentile of the written note lengths, in quarters.
fn short_note_q(score: &Score) -> f64 {
    let mut d: Vec<f64> = score.notes.iter().map(|n| n.dur_q).collect();
    d.sort_by(f64::total_cmp);
    d.get(d.len() / 10).copied().unwrap_or(1.0).max(1.0 / 16.0)
}

/// Performs `score` with a timing drawn from `seed`. `tempo_range_bpm` bounds the drawn
/// tempo when the score marks none (log-uniform), in notated beats per minute.
pub fn perform(score: &Score, seed: u64, tempo_range_bpm: (f64, f64)) -> Played {
    let mut rng = Rng::new(seed);
    let ts = score.main_time_signature();
    let beat_q = ts.beat_quarters();
    let bar_q = ts.bar_quarters();
    let (lo, hi) = (
        tempo_range_bpm.0.max(20.0),
        tempo_range_bpm.1.max(tempo_range_bpm.0 + 1.0),
    );
    let drawn = (lo.ln() + rng.unit() * (hi.ln() - lo.ln())).exp();
    let mut bpm = score
        .tempo_bpm
        .map_or(drawn, |t| t * rng.uniform(0.85, 1.15));
    // Never ask for more than MAX_NOTES_PER_S of the score's short notes.
    let max_bpm = MAX_NOTES_PER_S * 60.0 * short_note_q(score) / beat_q;
    bpm = bpm.min(max_bpm).clamp(lo.min(40.0), 200.0);
    let timing = TimingDraw {
        tempo_bpm: bpm,
        rubato_depth: [rng.uniform(0.0, 0.08), rng.uniform(0.0, 0.04)],
        final_ritardando: rng.uniform(0.55, 0.95),
        onset_noise_s: rng.uniform(0.003, 0.02),
        fermata_stretch: rng.uniform(1.5, 2.5),
    };
    let total_q = score.total_q();
    let curve = tempo_curve(score, &timing, &mut rng, bar_q, beat_q, total_q);

    let beats = score.beats_q();
    let beats_s: Vec<f64> = beats.iter().map(|(q, _)| curve.seconds(*q)).collect();
    let downbeats_s: Vec<f64> = beats
        .iter()
        .filter(|(_, d)| *d)
        .map(|(q, _)| curve.seconds(*q))
        .collect();
    let downbeat_q: Vec<f64> = beats.iter().filter(|(_, d)| *d).map(|(q, _)| *q).collect();
    let tempo_bpm_per_beat: Vec<f64> = beats_s
        .windows(2)
        .zip(&beats)
        .map(|(w, (q, _))| {
            let next_q = q + beat_q;
            60.0 * (next_q - q) / beat_q / (curve.seconds(next_q) - w[0]).max(1e-6)
        })
        .collect();

    // Dynamics for scores without marks: a level and slow hairpins.
    let base_level = rng.uniform(0.3, 0.8);
    let hairpin = (
        rng.uniform(0.1, 0.3),
        rng.uniform(2.0, 4.0) * bar_q,
        rng.uniform(0.0, std::f64::consts::TAU),
    );
    let mut notes: Vec<TimedNote> = Vec::with_capacity(score.notes.len());
    let mut prev_onset = f64::NEG_INFINITY;
    for (i, n) in score.notes.iter().enumerate() {
        let next = score.notes.get(i + 1);
        let nominal_on = curve.seconds(n.start_q);
        let nominal_end = curve.seconds(n.end_q());
        let dur = (nominal_end - nominal_on).max(0.01);
        let sigma = timing.onset_noise_s * if n.slurred_from_previous { 0.5 } else { 1.0 };
        let bound = (0.2 * dur).min(0.04);
        let jitter = (sigma * rng.normal()).clamp(-bound, bound);
        let onset = (nominal_on + jitter).max(prev_onset + 0.02).max(0.0);
        prev_onset = onset;
        let legato_into_next = next.is_some_and(|m| m.slurred_from_previous);
        let touching_next = next.is_some_and(|m| (m.start_q - n.end_q()).abs() < 1e-6);
        let sounding = if legato_into_next || n.fermata {
            dur
        } else if n.staccato {
            dur * rng.uniform(0.4, 0.6)
        } else if touching_next {
            dur - 0.03f64.min(0.08 * dur)
        } else {
            0.9 * dur
        };
        let dynamic = n.dynamic.map_or_else(
            || {
                base_level
                    + hairpin.0 * (std::f64::consts::TAU * n.start_q / hairpin.1 + hairpin.2).sin()
            },
            f64::from,
        ) + rng.uniform(-0.04, 0.04);
        let starts_bar = downbeat_q.iter().any(|q| (q - n.start_q).abs() < 1e-6);
        notes.push(TimedNote {
            note: Note::new(onset, onset + sounding.max(0.015), n.midi),
            bow_change: !n.slurred_from_previous,
            dynamic: dynamic.clamp(0.0, 1.0) as f32,
            accent: n.accent || (!n.slurred_from_previous && starts_bar && rng.chance(0.15)),
        });
    }
    // A note never sounds past the next onset; slurred notes join it.
    for i in 1..notes.len() {
        let next_on = notes[i].note.onset_s;
        let joined = !notes[i].bow_change;
        let prev = &mut notes[i - 1].note;
        if joined || prev.offset_s > next_on {
            prev.offset_s = next_on;
        }
        if prev.offset_s <= prev.onset_s {
            prev.offset_s = prev.onset_s + 0.01;
        }
    }
    let last_end = notes.last().map_or(0.0, |n| n.note.offset_s);
    let duration_s = curve.seconds(total_q).max(last_end) + TAIL_S;
    let arousal_2hz = arousal_proxy(&notes, duration_s);
    Played {
        timeline: Timeline {
            duration_s,
            notes,
            beats_s,
            downbeats_s,
            arousal_2hz,
            tempo_bpm: bpm,
        },
        time_signature: ts,
        tempo_bpm_per_beat,
        timing,
    }
}

/// Integrates the tempo: base × two rubato waves × a per-bar drift × phrase-end and final
/// ritardandi, with fermatas held `fermata_stretch` times their written length.
fn tempo_curve(
    score: &Score,
    t: &TimingDraw,
    rng: &mut Rng,
    bar_q: f64,
    beat_q: f64,
    total_q: f64,
) -> TempoCurve {
    let waves = [
        (
            t.rubato_depth[0],
            rng.uniform(4.0, 16.0) * bar_q,
            rng.uniform(0.0, std::f64::consts::TAU),
        ),
        (
            t.rubato_depth[1],
            rng.uniform(1.0, 3.0) * bar_q,
            rng.uniform(0.0, std::f64::consts::TAU),
        ),
    ];
    let bars = (total_q / bar_q).ceil() as usize + 2;
    let mut drift = Vec::with_capacity(bars);
    let mut d = 1.0f64;
    for _ in 0..bars {
        drift.push(d);
        d = (d + 0.02 * rng.normal()).clamp(0.88, 1.12);
    }
    // Phrase-end easing: every 8 bars, sometimes, the last beat slows to 80–90 %.
    let phrase_rits: Vec<(f64, f64)> = (1..=bars / 8)
        .filter_map(|k| {
            let at = (k * 8) as f64 * bar_q;
            (rng.chance(0.3) && at < total_q - bar_q).then(|| (at, rng.uniform(0.8, 0.9)))
        })
        .collect();
    let final_span = rng.uniform(1.0, 2.0) * bar_q;
    let fermatas: Vec<(f64, f64)> = score
        .notes
        .iter()
        .filter(|n| n.fermata)
        .map(|n| (n.start_q, n.end_q()))
        .collect();
    let factor = |q: f64| -> f64 {
        let mut f: f64 = waves
            .iter()
            .map(|(depth, period, phase)| {
                depth * (std::f64::consts::TAU * q / period + phase).sin()
            })
            .sum::<f64>()
            + 1.0;
        let b = (q / bar_q).max(0.0);
        let i = (b.floor() as usize).min(drift.len().saturating_sub(2));
        let frac = b - i as f64;
        f *= drift[i] * (1.0 - frac) + drift[(i + 1).min(drift.len() - 1)] * frac.min(1.0);
        for (at, depth) in &phrase_rits {
            let x = (q - (at - beat_q)) / beat_q;
            if (0.0..1.0).contains(&x) {
                f *= 1.0 - (1.0 - depth) * x;
            }
        }
        let x = (q - (total_q - final_span)) / final_span;
        if x > 0.0 {
            f *= 1.0 - (1.0 - t.final_ritardando) * x.min(1.0).powi(2);
        }
        if fermatas.iter().any(|(a, e)| q >= *a && q < *e) {
            f /= t.fermata_stretch;
        }
        f.max(0.2)
    };
    let n = (total_q * STEPS_PER_Q).ceil() as usize + 2;
    let mut table = Vec::with_capacity(n);
    let mut s = 0.0;
    let step_s = 60.0 / (t.tempo_bpm * beat_q) / STEPS_PER_Q;
    for i in 0..n {
        table.push(s);
        s += step_s / factor((i as f64 + 0.5) / STEPS_PER_Q);
    }
    TempoCurve { table }
}

/// Bow strokes of a fingered timeline: one per bow change, with the direction the analysis
/// uses too ([`performance::bow_directions`]: alternation, a pickup starts up-bow, a retake
/// to down-bow on a downbeat after a rest) and the string of the stroke's first note.
pub fn bow_strokes(timeline: &Timeline) -> Vec<BowStroke> {
    let notes: Vec<Note> = timeline.notes.iter().map(|n| n.note).collect();
    let changes = timeline.bow_changes_s();
    let directions = bow_directions(&changes, &notes, &timeline.downbeats_s);
    performance::strokes_of(&changes, &directions, &notes)
}

/// The range of a player's adherence to "a bar starts down-bow": the chance, drawn once
/// per item, that they hook a stroke where a bar would otherwise start up-bow.
pub const HOOK_ADHERENCE: (f64, f64) = (0.7, 1.0);

/// Plays some strokes hooked, as violinists bow: where a bar would start up-bow, the two
/// strokes before it are joined into one bow ([`Timeline::hook_to_downbeats`]) with a
/// probability drawn from [`HOOK_ADHERENCE`] for the item. Returns the number of hooks.
pub fn hook_to_downbeats(timeline: &mut Timeline, rng: &mut Rng) -> usize {
    let adherence = rng.uniform(HOOK_ADHERENCE.0, HOOK_ADHERENCE.1);
    timeline.hook_to_downbeats(|_| rng.chance(adherence))
}
