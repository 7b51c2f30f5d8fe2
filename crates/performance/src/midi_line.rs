//! From a [`MidiScore`] to what motion needs: the beat grid (from time signatures, or
//! inferred from the notes), one melodic line, and bowing by the rules of [`crate::midi`].

use crate::meter::Meter;
use crate::midi_score::{MidiNote, MidiScore};
use crate::note::{Note, CHORD_S};
use crate::timeline::{arousal_proxy, TimedNote, Timeline};

/// [`MidiBowing::notated_below_share`]'s default.
const NOTATED_BELOW_SHARE: f64 = 0.2;
/// The most beats a grid has (an hour at 1000 bpm in 32nd-note beats is far below).
const MAX_BEATS: usize = 2_000_000;

/// Beats, downbeats and the first bar's meter.
pub(crate) struct Grid {
    pub beats_s: Vec<f64>,
    pub downbeats_s: Vec<f64>,
    pub meter: Meter,
    pub from_file: bool,
}

/// (beat length in ticks, beats per bar, subdivisions) of a time signature.
fn beat_of(num: u32, den: u32, ticks_per_quarter: f64) -> (f64, u32, u8) {
    let compound = den == 8 && num.is_multiple_of(3) && num > 3;
    if compound {
        (1.5 * ticks_per_quarter, num / 3, 3)
    } else {
        (4.0 / f64::from(den) * ticks_per_quarter, num, 2)
    }
}

/// The bar length (2, 3 or 4 quarter beats) and phase that put the most duration ×
/// velocity on downbeats, relative to what an even spread would put there (ties → 4).
fn infer_meter(notes: &[(u64, u64, u8, u8, u8)], tpq: f64) -> (u32, u64) {
    let mut best = (f64::NEG_INFINITY, 4u32, 0u64);
    for bpb in [4u32, 3, 2] {
        let mut weight = vec![0.0f64; bpb as usize];
        let mut total = 0.0;
        for &(on, off, _, vel, _) in notes {
            let beat = on as f64 / tpq;
            if (beat - beat.round()).abs() > 0.125 {
                continue;
            }
            let w = ((off - on) as f64 / tpq).min(4.0) * f64::from(vel);
            let slot = (beat.round() as u64 % u64::from(bpb)) as usize;
            if let Some(x) = weight.get_mut(slot) {
                *x += w;
            }
            total += w;
        }
        if total <= 0.0 {
            continue;
        }
        for (phase, &w) in weight.iter().enumerate() {
            let ratio = w / total * f64::from(bpb);
            if ratio > best.0 + 1e-9 {
                best = (ratio, bpb, phase as u64);
            }
        }
    }
    (best.1, best.2)
}

/// The beat grid from the time signatures (every change), or inferred from the notes when
/// the file has none.
pub(crate) fn beat_grid(
    signatures: &[(u64, u32, u32)],
    notes: &[(u64, u64, u8, u8, u8)],
    tpq: f64,
    last_tick: u64,
    seconds: impl Fn(f64) -> f64,
) -> Grid {
    let mut sigs: Vec<(u64, u32, u32)> = signatures.to_vec();
    sigs.sort_by_key(|s| s.0);
    // The last signature at a tick wins.
    let mut dedup: Vec<(u64, u32, u32)> = Vec::with_capacity(sigs.len());
    for s in sigs {
        match dedup.last_mut() {
            Some(last) if last.0 == s.0 => *last = s,
            _ => dedup.push(s),
        }
    }
    let from_file = !dedup.is_empty();
    // Beat index (from the file's start) of the first downbeat: earlier beats are a pickup.
    let mut phase = 0u64;
    if dedup.is_empty() {
        let (bpb, p) = infer_meter(notes, tpq);
        phase = p;
        dedup.push((0, bpb, 4));
    } else if let Some(first) = dedup.first_mut() {
        first.0 = 0; // a first signature after tick 0 also rules the bars before it
    }
    let (_, num, den) = dedup[0];
    let (_, bpb0, sub0) = beat_of(num, den, tpq);
    let meter = Meter {
        beats_per_bar: u8::try_from(bpb0).unwrap_or(u8::MAX),
        subdivisions: sub0,
    };
    let (mut beats_s, mut downbeats_s) = (Vec::new(), Vec::new());
    for (i, &(tick, num, den)) in dedup.iter().enumerate() {
        let end = dedup
            .get(i + 1)
            .map_or(last_tick as f64 + 1e-9, |n| n.0 as f64 - 1e-9);
        let (beat_ticks, bpb, _) = beat_of(num, den, tpq);
        let bpb = u64::from(bpb.max(1));
        let phase = if i == 0 { phase % bpb } else { 0 };
        let mut k = 0u64;
        loop {
            let t = tick as f64 + k as f64 * beat_ticks;
            if t > end || beats_s.len() >= MAX_BEATS {
                break;
            }
            let s = seconds(t);
            if beats_s.last().is_none_or(|&l| s > l) {
                beats_s.push(s);
                if k >= phase && (k - phase).is_multiple_of(bpb) {
                    downbeats_s.push(s);
                }
            }
            k += 1;
        }
    }
    Grid {
        beats_s,
        downbeats_s,
        meter,
        from_file,
    }
}

/// One melodic line: chords keep their highest note, overlaps cut the earlier note.
pub(crate) fn reduce_to_line(notes: &[MidiNote]) -> Vec<TimedNote> {
    let mut out: Vec<TimedNote> = Vec::new();
    for n in notes {
        if let Some(prev) = out.last_mut() {
            if n.onset_s - prev.note.onset_s < CHORD_S {
                continue; // lower note of a chord (sorted highest first)
            }
            if prev.note.offset_s > n.onset_s {
                prev.note.offset_s = n.onset_s;
            }
        }
        out.push(TimedNote {
            note: Note {
                velocity: Some(n.velocity),
                ..Note::new(n.onset_s, n.offset_s, n.midi)
            },
            bow_change: true,
            dynamic: f32::from(n.velocity) / 127.0,
            accent: false,
        });
    }
    out
}

/// The share of consecutive notes of the score's melodic line (chords count once) that a
/// gap of at least `gap_s` separates: near 0 when the file's notes touch as notated (a
/// notation program's export), well above it when the timing was played or articulated.
///
/// ```
/// use performance::midi::{separated_share, MidiNote, MidiScore};
/// use performance::Meter;
/// let note = |on: f64, off: f64| MidiNote { onset_s: on, offset_s: off, midi: 67, velocity: 80, channel: 0 };
/// let score = |notes| MidiScore {
///     notes, beats_s: vec![0.0], downbeats_s: vec![0.0], meter: Meter::FOUR_FOUR,
///     meter_from_file: true, tempo_bpm: 120.0, duration_s: 2.0, transposed: 0,
/// };
/// let touching = score(vec![note(0.0, 0.5), note(0.5, 1.0), note(1.0, 1.5)]);
/// assert_eq!(separated_share(&touching, 0.001), 0.0);
/// let played = score(vec![note(0.0, 0.45), note(0.5, 1.0), note(1.0, 1.4)]);
/// assert_eq!(separated_share(&played, 0.001), 0.5);
/// ```
pub fn separated_share(score: &MidiScore, gap_s: f64) -> f64 {
    line_separated_share(&reduce_to_line(&score.notes), gap_s)
}

/// Whether the score's timing is notated rather than played: its notes touch (fewer than
/// [`MidiBowing::notated_below_share`] apart by a gap of `legato_gap_s`) and nine in ten
/// onsets sit on the beat grid (a 48th of a beat, within a tenth of that). A notation
/// program's export is both; a played or humanised file is neither, and a legato passage
/// played without gaps still has its onsets off the grid.
pub fn timing_is_notated(score: &MidiScore, rules: &MidiBowing) -> bool {
    notated(&reduce_to_line(&score.notes), &score.beats_s, rules)
}

fn notated(line: &[TimedNote], beats_s: &[f64], rules: &MidiBowing) -> bool {
    line_separated_share(line, rules.legato_gap_s) < rules.notated_below_share
        && on_grid_share(line, beats_s) >= 0.9
}

/// The share of the line's onsets within a tenth of a 48th of a beat of that grid.
fn on_grid_share(line: &[TimedNote], beats_s: &[f64]) -> f64 {
    let (mut on, mut n) = (0usize, 0usize);
    for t in line {
        let x = t.note.onset_s;
        let k = beats_s.partition_point(|&b| b <= x).saturating_sub(1);
        let (Some(&b0), Some(&b1)) = (beats_s.get(k), beats_s.get(k + 1)) else {
            continue;
        };
        if b1 <= b0 {
            continue;
        }
        let pos = (x - b0) / (b1 - b0) * 48.0;
        n += 1;
        on += usize::from((pos - pos.round()).abs() < 0.1);
    }
    if n == 0 {
        0.0
    } else {
        on as f64 / n as f64
    }
}

fn line_separated_share(line: &[TimedNote], gap_s: f64) -> f64 {
    let (mut separated, mut pairs) = (0usize, 0usize);
    for w in line.windows(2) {
        pairs += 1;
        separated += usize::from(w[1].note.onset_s - w[0].note.offset_s >= gap_s);
    }
    if pairs == 0 {
        1.0
    } else {
        separated as f64 / pairs as f64
    }
}

/// When a MIDI note continues the previous note's bow (a slur) rather than starting a new
/// stroke: all of these must hold, and the note must not start a bar.
///
/// The defaults were chosen on the validation split of the many-violin corpus
/// (`cargo run --release -p violin-train --example tune_midi_bowing -- CORPUS`): bow-change
/// F 0.874 against the labelled bowing, where the earlier hand-set rules (a 30 ms legato
/// gap, 4 notes, 2 s, a velocity step of 20) gave 0.535. Slurred notes join with no gap;
/// a separate bow leaves one, often of only a few milliseconds.
///
/// ```
/// use performance::midi::MidiBowing;
/// let rules = MidiBowing { max_slur_notes: 2, ..MidiBowing::default() };
/// assert!(rules.legato_gap_s < 0.05);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MidiBowing {
    /// The note starts less than this after the previous note ends (legato), seconds.
    pub legato_gap_s: f64,
    /// The slur already holds fewer notes than this.
    pub max_slur_notes: usize,
    /// … or fewer than this when the note is short (under `short_note_s`).
    pub max_slur_notes_short: usize,
    /// What counts as a short note, seconds.
    pub short_note_s: f64,
    /// The bow has been moving for less than this when the note ends, seconds.
    pub max_bow_s: f64,
    /// The velocity differs from the previous note's by at most this.
    pub max_velocity_step: u8,
    /// When fewer than this share of the line's consecutive notes are apart by at least
    /// `legato_gap_s` ([`separated_share`]), the timing carries no articulation (notes
    /// touch as notated), the gaps cannot tell slurs from separate bows, and the rules of
    /// [`MidiBowing::NOTATED`] apply instead.
    pub notated_below_share: f64,
}

impl MidiBowing {
    /// The rules for notated timing: every note takes a new bow except notes shorter than
    /// 0.125 s (ornaments, the fastest runs), slurred up to 6 and for at most 1 s. Chosen
    /// against real players' bowing, on half of the YTVF dataset's works (`cargo run
    /// --release -p violin-train --example ytvf_bowing -- YTVF_DIR 100 --grid`). On the
    /// other half, with [`timing_is_notated`] choosing the works they apply to, bow-change
    /// F 0.690 and direction 0.577 of notes, where the rules for played timing gave 0.424
    /// and 0.535 by slurring whatever touches.
    pub const NOTATED: MidiBowing = MidiBowing {
        legato_gap_s: 0.001,
        max_slur_notes: 1,
        max_slur_notes_short: 6,
        short_note_s: 0.125,
        max_bow_s: 1.0,
        max_velocity_step: 10,
        notated_below_share: 0.0,
    };
}

impl Default for MidiBowing {
    fn default() -> Self {
        MidiBowing {
            legato_gap_s: 0.001,
            max_slur_notes: 6,
            max_slur_notes_short: 8,
            short_note_s: 0.2,
            max_bow_s: 3.0,
            max_velocity_step: 10,
            notated_below_share: NOTATED_BELOW_SHARE,
        }
    }
}

/// Marks each note of the line as a new stroke or a slur, by `rules`.
pub(crate) fn assign_bowing(
    mut notes: Vec<TimedNote>,
    downbeats_s: &[f64],
    rules: &MidiBowing,
) -> Vec<TimedNote> {
    let mut slur_len = 0usize;
    let mut stroke_start = 0.0;
    for i in 0..notes.len() {
        let onset = notes[i].note.onset_s;
        let d = downbeats_s.partition_point(|&d| d < onset - 0.02);
        let on_downbeat = downbeats_s
            .get(d)
            .is_some_and(|&d| (d - onset).abs() < 0.02);
        let slurred = i > 0 && {
            let prev = &notes[i - 1];
            let cur = &notes[i];
            let short = cur.note.offset_s - cur.note.onset_s < rules.short_note_s;
            let cap = if short {
                rules.max_slur_notes_short
            } else {
                rules.max_slur_notes
            };
            cur.note.onset_s - prev.note.offset_s < rules.legato_gap_s
                && slur_len < cap
                && cur.note.offset_s - stroke_start < rules.max_bow_s
                && !on_downbeat
                && (cur.dynamic - prev.dynamic).abs() * 127.0 <= f32::from(rules.max_velocity_step)
        };
        if slurred {
            slur_len += 1;
        } else {
            slur_len = 1;
            stroke_start = onset;
        }
        notes[i].bow_change = !slurred;
        notes[i].accent = on_downbeat && !slurred;
    }
    notes
}

/// The line of a score with its bowing (the default [`MidiBowing`]), dynamics and arousal.
pub fn timeline_from_score(score: &MidiScore) -> Timeline {
    timeline_from_score_with(score, &MidiBowing::default())
}

/// [`timeline_from_score`] with other bowing rules.
pub fn timeline_from_score_with(score: &MidiScore, bowing: &MidiBowing) -> Timeline {
    let line = reduce_to_line(&score.notes);
    let rules = if notated(&line, &score.beats_s, bowing) {
        &MidiBowing::NOTATED
    } else {
        bowing
    };
    let notes = assign_bowing(line, &score.downbeats_s, rules);
    let duration_s = score.duration_s;
    let arousal_2hz = arousal_proxy(&notes, duration_s);
    let mut timeline = Timeline {
        duration_s,
        tempo_bpm: score.tempo_bpm,
        notes,
        beats_s: score.beats_s.clone(),
        downbeats_s: score.downbeats_s.clone(),
        arousal_2hz,
    };
    timeline.hook_to_downbeats(|_| true);
    timeline
}
