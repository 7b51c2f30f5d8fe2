//! The MIDI bowing rules ([`performance::midi::MidiBowing`]) against real players: every
//! work of the YTVF dataset (`fingering::ytvf`; 30 works, each one professional performance
//! with every note's bow direction annotated from its video) is turned into the MIDI file a
//! notation program would write (notes as notated, touching unless a rest separates them;
//! velocity 80; one tempo; downbeats at the bars), bowed by the rules, and compared with the
//! player's directions:
//!
//! * bow changes: between consecutive bowed notes (not pizzicato, not one chord) the player
//!   changes bow where the labelled directions differ; precision, recall and F of the
//!   rules' changes at those notes;
//! * directions: the share of bowed notes whose stroke goes the player's way.
//!
//! Works are split in two halves by a stable hash of the file name (`tune` and `test`), so
//! that rules for this kind of input can be chosen on one half and checked on the other.
//!
//! ```text
//! cargo run --release -p violin-train --example ytvf_bowing -- YTVF_DIR [BPM]
//! ```

use std::path::{Path, PathBuf};

use fingering::ytvf::{read_ytvf_notes, YtvfNote};
use performance::midi::{
    separated_share, timeline_from_score_with, timing_is_notated, MidiBowing, MidiNote, MidiScore,
};
use performance::{bow_directions, strokes_of, BowDirection, Meter, Note};

/// One work: its score as MIDI and the player's direction per bowed note (onset, down?).
struct Work {
    name: String,
    score: MidiScore,
    bowed: Vec<(f64, bool)>,
}

/// Even [`corpus::schedule::work_hash`] of the name → `tune`, odd → `test`.
fn is_tune(name: &str) -> bool {
    corpus::schedule::work_hash(name).is_multiple_of(2)
}

/// Bar starts in beats for bars `first..=last`: a bar lasts the work's usual length, or
/// longer where its notes start later (a change of metre).
fn bar_starts(notes: &[YtvfNote]) -> (i32, Vec<f64>, f64) {
    let first = notes.iter().map(|n| n.bar).min().unwrap_or(0);
    let last = notes.iter().map(|n| n.bar).max().unwrap_or(0);
    let span = usize::try_from(last - first + 1).unwrap_or(1);
    let (mut ends, mut starts_max) = (vec![0.0f64; span], vec![0.0f64; span]);
    for n in notes {
        let k = (n.bar - first) as usize;
        ends[k] = ends[k].max(n.start_beats + n.duration_beats);
        starts_max[k] = starts_max[k].max(n.start_beats);
    }
    let mut lengths: Vec<f64> = ends.iter().copied().filter(|&e| e > 0.0).collect();
    lengths.sort_by(f64::total_cmp);
    let usual = ((lengths.get(lengths.len() / 2).copied().unwrap_or(4.0)) * 4.0).round() / 4.0;
    let mut starts = Vec::with_capacity(span + 1);
    let mut t = 0.0;
    for &s in &starts_max {
        starts.push(t);
        t += usual.max(((s + 1e-3) * 2.0).ceil() / 2.0);
    }
    starts.push(t);
    (first, starts, usual)
}

fn work(path: &Path, bpm: f64) -> Result<Work, Box<dyn std::error::Error>> {
    let notes = read_ytvf_notes(path)?;
    let (first, starts, usual) = bar_starts(&notes);
    let s_per_beat = 60.0 / bpm;
    let onset = |n: &YtvfNote| (starts[(n.bar - first) as usize] + n.start_beats) * s_per_beat;
    let mut midi: Vec<MidiNote> = notes
        .iter()
        .map(|n| MidiNote {
            onset_s: onset(n),
            offset_s: onset(n) + n.duration_beats.max(0.01) * s_per_beat,
            midi: n.midi,
            velocity: 80,
            channel: 0,
        })
        .collect();
    midi.sort_by(|a, b| a.onset_s.total_cmp(&b.onset_s).then(b.midi.cmp(&a.midi)));
    let end_beats = starts.last().copied().unwrap_or(0.0);
    let beats_s: Vec<f64> = (0..end_beats.ceil() as usize)
        .map(|b| b as f64 * s_per_beat)
        .collect();
    let downbeats_s: Vec<f64> = starts.iter().map(|b| b * s_per_beat).collect();
    let mut bowed: Vec<(f64, bool)> = (notes.iter())
        .filter(|n| n.bowing == 1 || n.bowing == 2)
        .map(|n| (onset(n), n.bowing == 1))
        .collect();
    bowed.sort_by(|a, b| a.0.total_cmp(&b.0));
    bowed.dedup_by(|b, a| (b.0 - a.0).abs() < 1e-6); // a chord is one stroke
    let duration_s = midi.iter().map(|n| n.offset_s).fold(0.0, f64::max) + 0.5;
    Ok(Work {
        name: path
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().to_string()),
        score: MidiScore {
            notes: midi,
            beats_s,
            downbeats_s,
            meter: Meter {
                beats_per_bar: usual.round().clamp(1.0, 12.0) as u8,
                subdivisions: 2,
            },
            meter_from_file: true,
            tempo_bpm: bpm,
            duration_s,
            transposed: 0,
        },
        bowed,
    })
}

/// (changes matched, labelled, found, directions right, bowed notes).
fn measure(w: &Work, rules: &MidiBowing) -> [usize; 5] {
    let timeline = timeline_from_score_with(&w.score, rules);
    let changes = timeline.bow_changes_s();
    let notes: Vec<Note> = timeline.notes.iter().map(|n| n.note).collect();
    let directions = bow_directions(&changes, &notes, &w.score.downbeats_s);
    let strokes = strokes_of(&changes, &directions, &notes);
    let changed_at = |t: f64| changes.iter().any(|c| (c - t).abs() < 1e-4);
    let mut m = [0usize; 5];
    for pair in w.bowed.windows(2) {
        let labelled = pair[0].1 != pair[1].1;
        let found = changed_at(pair[1].0);
        m[0] += usize::from(labelled && found);
        m[1] += usize::from(labelled);
        m[2] += usize::from(found);
    }
    for &(t, down) in &w.bowed {
        let k = strokes.partition_point(|s| s.start_s <= t + 1e-4);
        if let Some(s) = k.checked_sub(1).and_then(|k| strokes.get(k)) {
            m[3] += usize::from((s.direction == BowDirection::Down) == down);
        }
        m[4] += 1;
    }
    m
}

fn line(name: &str, m: [usize; 5]) -> String {
    let p = m[0] as f64 / m[2].max(1) as f64;
    let r = m[0] as f64 / m[1].max(1) as f64;
    format!(
        "{name}: bow-change F {:.3} (P {p:.3}, R {r:.3}; {} labelled), direction {:.3} of {} notes",
        performance::f_measure(p, r),
        m[1],
        m[3] as f64 / m[4].max(1) as f64,
        m[4]
    )
}

fn total(works: &[&Work], rules: &MidiBowing) -> [usize; 5] {
    works.iter().fold([0; 5], |mut acc, w| {
        for (a, b) in acc.iter_mut().zip(measure(w, rules)) {
            *a += b;
        }
        acc
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = PathBuf::from(args.first().ok_or("usage: ytvf_bowing YTVF_DIR [BPM]")?);
    let bpm: f64 = args.get(1).map_or(Ok(100.0), |v| v.parse())?;
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)?
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "csv"))
        .collect();
    paths.sort();
    let works = paths
        .iter()
        .map(|p| work(p, bpm))
        .collect::<Result<Vec<_>, _>>()?;
    let rules = MidiBowing::default();
    // The rules for played timing, applied whatever the timing (as before notated timing
    // was recognised).
    let played = MidiBowing {
        notated_below_share: 0.0,
        ..rules
    };
    let (tune, test): (Vec<&Work>, Vec<&Work>) = works.iter().partition(|w| is_tune(&w.name));
    println!(
        "{} works at {bpm} bpm; default rules {rules:?}",
        works.len()
    );
    for w in &works {
        let half = if is_tune(&w.name) { "tune" } else { "test" };
        let share = separated_share(&w.score, rules.legato_gap_s);
        let notated = if timing_is_notated(&w.score, &rules) {
            "notated"
        } else {
            "played"
        };
        let name = format!("  {half} {} (separated {share:.3}, {notated})", w.name);
        println!("{}", line(&name, measure(w, &rules)));
    }
    let all: Vec<&Work> = works.iter().collect();
    for (name, r) in [("default rules", &rules), ("played-timing rules", &played)] {
        println!("{name}:");
        println!(
            "{}",
            line(&format!("  tune ({} works)", tune.len()), total(&tune, r))
        );
        println!(
            "{}",
            line(&format!("  test ({} works)", test.len()), total(&test, r))
        );
        println!("{}", line("  all", total(&all, r)));
    }
    if args.iter().any(|a| a == "--grid") {
        let mut results = Vec::new();
        for max_slur_notes in [1, 2, 3, 4] {
            for max_slur_notes_short in [1, 2, 3, 4, 6, 8] {
                for short_note_s in [0.0, 0.05, 0.075, 0.1, 0.125, 0.15, 0.2, 0.3] {
                    for max_bow_s in [1.0, 1.5, 2.0, 3.0] {
                        let r = MidiBowing {
                            max_slur_notes,
                            max_slur_notes_short,
                            short_note_s,
                            max_bow_s,
                            ..played
                        };
                        let m = total(&tune, &r);
                        let p = m[0] as f64 / m[2].max(1) as f64;
                        let q = m[0] as f64 / m[1].max(1) as f64;
                        results.push((performance::f_measure(p, q), r, m));
                    }
                }
            }
        }
        results.sort_by(|a, b| b.0.total_cmp(&a.0));
        for below in [0.1, 0.2, 0.3] {
            let r = MidiBowing {
                notated_below_share: below,
                ..rules
            };
            println!(
                "{}",
                line(&format!("tune, notated below {below}"), total(&tune, &r))
            );
        }
        for (_, r, m) in results.iter().take(5) {
            println!("{}", line(&format!("tune, {r:?}"), *m));
        }
        if let Some((_, best, _)) = results.first() {
            println!("{}", line("test, best on tune", total(&test, best)));
        }
    }
    Ok(())
}
