//! For the same music, how far the analysis of the recording agrees with the analysis of its
//! MIDI score (issue 22: "audio and MIDI analyses agree where they can").
//!
//! Each test item of a corpus made by `violin-skeleton corpus` is analysed twice by the
//! default [`Pipeline`]: its `audio.wav`, and its score as a MIDI file would give it — the
//! labelled notes (double stops included; velocity from the note's dynamic), beats, downbeats
//! and time signature, handed to [`Pipeline::analyze_midi_score`] as the `MidiScore` that
//! reading a type-1 file with that tempo map and time signature produces. The MIDI analysis
//! is the reference; per evaluation set this prints:
//!
//! * notes: onset F (±50 ms), and over the matched notes the same pitch, the same string,
//!   the same string and position (an open string on both sides counts on the string);
//! * beats and downbeats F (±70 ms, the first 5 s ignored), the same beats per bar, a tempo
//!   within 8 %;
//! * bow changes F (±100 ms), and over the matched changes the same stroke direction;
//! * arousal: Pearson correlation of the two curves.
//!
//! `cargo run --release -p violin-train --example audio_midi_agreement -- CORPUS`

use std::collections::BTreeMap;
use std::path::Path;

use performance::{event_prf, match_events};
use rayon::prelude::*;
use violin_skeleton::{Analysis, Pipeline};
use violin_train::beat_data::read_first_column;
use violin_train::bowing_data::read_strokes;
use violin_train::evaluate::{direction_tally, find_recordings, SplitChoice};
use violin_train::item_score::item_midi_score;

/// Sums of per-item figures and their counts, by name.
#[derive(Default)]
struct Sums(BTreeMap<&'static str, (f64, usize)>);

impl Sums {
    fn add(&mut self, name: &'static str, value: Option<f64>) {
        if let Some(v) = value.filter(|v| v.is_finite()) {
            let e = self.0.entry(name).or_default();
            e.0 += v;
            e.1 += 1;
        }
    }
    fn mean(&self, name: &str) -> String {
        self.0.get(name).map_or("–".into(), |(s, n)| {
            format!("{:.3}", s / (*n).max(1) as f64)
        })
    }
}

/// Share of `pairs` for which `same` holds (None without pairs).
fn share(pairs: &[(usize, usize)], same: impl Fn(usize, usize) -> bool) -> Option<f64> {
    (!pairs.is_empty())
        .then(|| pairs.iter().filter(|(r, e)| same(*r, *e)).count() as f64 / pairs.len() as f64)
}

fn compare(midi: &Analysis, audio: &Analysis, sums: &mut Sums) {
    let onsets = |a: &Analysis| a.notes.iter().map(|n| n.onset_s).collect::<Vec<_>>();
    let (mo, ao) = (onsets(midi), onsets(audio));
    sums.add("note onset F", Some(event_prf(&mo, &ao, 0.05).f_measure));
    let pairs = match_events(&mo, &ao, 0.05);
    let (mn, an) = (&midi.notes, &audio.notes);
    sums.add("same pitch", share(&pairs, |r, e| mn[r].midi == an[e].midi));
    let same_pitch: Vec<(usize, usize)> = pairs
        .iter()
        .copied()
        .filter(|&(r, e)| mn[r].midi == an[e].midi)
        .collect();
    let fingering = |i: usize, a: &[violin_skeleton::Note]| a[i].fingering;
    sums.add(
        "same string",
        share(&same_pitch, |r, e| {
            matches!((fingering(r, mn), fingering(e, an)), (Some(x), Some(y)) if x.string == y.string)
        }),
    );
    sums.add(
        "same string+position",
        share(&same_pitch, |r, e| {
            match (fingering(r, mn), fingering(e, an)) {
                (Some(x), Some(y)) => {
                    x.string == y.string
                        && ((x.finger == 0 && y.finger == 0) || x.position == y.position)
                }
                _ => false,
            }
        }),
    );
    let tr = |v: &[f64]| beat_track::eval::trim_beats(v, 5.0);
    sums.add(
        "beat F",
        Some(event_prf(&tr(&midi.beats_s), &tr(&audio.beats_s), 0.07).f_measure),
    );
    sums.add(
        "downbeat F",
        Some(event_prf(&tr(&midi.downbeats_s), &tr(&audio.downbeats_s), 0.07).f_measure),
    );
    let bar = |a: &Analysis| a.meter.map(|m| m.beats_per_bar);
    sums.add(
        "same beats per bar",
        Some(f64::from(u8::from(bar(midi) == bar(audio)))),
    );
    let tempo_ok = (audio.tempo_bpm / midi.tempo_bpm - 1.0).abs() <= 0.08;
    sums.add("tempo within 8 %", Some(f64::from(u8::from(tempo_ok))));
    let after = |v: &[f64]| v.iter().copied().filter(|t| *t >= 0.1).collect::<Vec<_>>();
    let (mb, ab) = (after(&midi.bow_changes_s), after(&audio.bow_changes_s));
    sums.add("bow change F", Some(event_prf(&mb, &ab, 0.1).f_measure));
    // Directions of the matched changes, looked up by time in each analysis.
    let dir_at = |a: &Analysis, t: f64| {
        a.bow_changes_s
            .iter()
            .position(|&c| (c - t).abs() < 1e-9)
            .and_then(|i| a.bow_directions.get(i).copied())
    };
    let changes = match_events(&mb, &ab, 0.1);
    sums.add(
        "same direction",
        share(&changes, |r, e| {
            dir_at(midi, mb[r]).is_some() && dir_at(midi, mb[r]) == dir_at(audio, ab[e])
        }),
    );
    sums.add(
        "arousal correlation",
        Some(emotion_net::estimator::pearson(
            &midi.arousal.values,
            &audio.arousal.values,
        )),
    );
}

/// Both analyses' bow changes (F, ±100 ms) and stroke directions against the item's
/// labelled bowing.
fn against_labels(
    item: &Path,
    midi: &Analysis,
    audio: &Analysis,
    sums: &mut Sums,
) -> Result<(), String> {
    let after = |v: &[f64]| v.iter().copied().filter(|t| *t >= 0.1).collect::<Vec<_>>();
    let truth = after(&read_first_column(&item.join("bowchanges.txt")).map_err(|e| e.to_string())?);
    let strokes = read_strokes(&item.join("strokes.tsv")).map_err(|e| e.to_string())?;
    for (name, a) in [("MIDI", midi), ("audio", audio)] {
        let f = event_prf(&truth, &after(&a.bow_changes_s), 0.1).f_measure;
        let d = direction_tally(&strokes, &a.bow_strokes).share();
        sums.add(
            if name == "MIDI" {
                "MIDI bow changes against the labels, F"
            } else {
                "audio bow changes against the labels, F"
            },
            Some(f),
        );
        sums.add(
            if name == "MIDI" {
                "MIDI stroke directions against the labels"
            } else {
                "audio stroke directions against the labels"
            },
            Some(d),
        );
    }
    Ok(())
}

const ROWS: [&str; 16] = [
    "MIDI bow changes against the labels, F",
    "audio bow changes against the labels, F",
    "MIDI stroke directions against the labels",
    "audio stroke directions against the labels",
    "note onset F",
    "same pitch",
    "same string",
    "same string+position",
    "beat F",
    "downbeat F",
    "same beats per bar",
    "tempo within 8 %",
    "bow change F",
    "same direction",
    "arousal correlation",
    "items",
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .ok_or("usage: audio_midi_agreement CORPUS")?;
    let (_, recordings) = find_recordings(Path::new(&dir), SplitChoice::Test)?;
    let pipeline = Pipeline::default();
    let results: Vec<(String, Sums)> = recordings
        .par_iter()
        .map(|rec| -> Result<(String, Sums), String> {
            let item = rec.audio.parent().ok_or("an audio file with no folder")?;
            let score = item_midi_score(item).map_err(|e| e.to_string())?;
            let midi = pipeline.analyze_midi_score(&score);
            let audio = pipeline
                .analyze_file(&rec.audio, |_, _| {})
                .map_err(|e| format!("{}: {e}", rec.audio.display()))?;
            let mut sums = Sums::default();
            compare(&midi, &audio, &mut sums);
            against_labels(item, &midi, &audio, &mut sums)?;
            sums.add("items", Some(1.0));
            Ok((rec.group.clone(), sums))
        })
        .collect::<Result<_, _>>()?;
    let mut by_set: BTreeMap<String, Sums> = BTreeMap::new();
    for (group, sums) in results {
        let total = by_set.entry(group).or_default();
        for (name, (s, n)) in sums.0 {
            let e = total.0.entry(name).or_default();
            e.0 += s;
            e.1 += n;
        }
    }
    let sets: Vec<&String> = by_set.keys().collect();
    println!(
        "| audio against MIDI, same music | {} |",
        sets.iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join(" | ")
    );
    println!("|---|{}", "---|".repeat(sets.len()));
    for row in ROWS {
        let cells: Vec<String> = sets
            .iter()
            .map(|s| {
                if row == "items" {
                    by_set[*s].0.get("items").map_or(0, |e| e.1).to_string()
                } else {
                    by_set[*s].mean(row)
                }
            })
            .collect();
        println!("| {row} | {} |", cells.join(" | "));
    }
    Ok(())
}
