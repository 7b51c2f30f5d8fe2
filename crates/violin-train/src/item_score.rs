//! A corpus item's score as a MIDI file would give it: the labelled notes (`notes.tsv` and
//! `double_stops.tsv`; velocity from each note's dynamic), beats, downbeats and time
//! signature, as the [`MidiScore`] that reading a type-1 file with that tempo map and time
//! signature produces. Used to compare the MIDI route with the audio route on the same
//! music, and to choose the MIDI bowing rules ([`performance::midi::MidiBowing`]).

use std::path::Path;

use performance::midi::{MidiNote, MidiScore};
use performance::Meter;

use crate::beat_data::{notated_meter, read_first_column};
use crate::error::{Result, TrainError};

fn bad(path: &Path, reason: impl Into<String>) -> TrainError {
    TrainError::Dataset {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}

/// The notes of `notes.tsv` and `double_stops.tsv` (onset, offset, midi, …, dynamic 0–1
/// last), in time order, highest first within a chord.
fn item_notes(dir: &Path) -> Result<Vec<MidiNote>> {
    let mut notes = Vec::new();
    for file in ["notes.tsv", "double_stops.tsv"] {
        let path = dir.join(file);
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(_) if file == "double_stops.tsv" => continue,
            Err(e) => return Err(bad(&path, format!("cannot read ({e})"))),
        };
        for (i, line) in text.lines().enumerate().skip(1) {
            if line.trim().is_empty() {
                continue;
            }
            let cols: Vec<&str> = line.split('\t').collect();
            let num = |k: usize| -> Result<f64> {
                cols.get(k)
                    .and_then(|c| c.trim().parse::<f64>().ok())
                    .filter(|v| v.is_finite() && *v >= 0.0)
                    .ok_or_else(|| {
                        bad(
                            &path,
                            format!("line {}: column {} is not a number", i + 1, k + 1),
                        )
                    })
            };
            let (onset_s, offset_s, midi) = (num(0)?, num(1)?, num(2)?);
            let dynamic = cols
                .last()
                .and_then(|c| c.trim().parse::<f64>().ok())
                .filter(|d| d.is_finite())
                .unwrap_or(0.6);
            notes.push(MidiNote {
                onset_s,
                offset_s: offset_s.max(onset_s),
                midi: midi.min(127.0) as u8,
                velocity: (dynamic * 127.0).round().clamp(1.0, 127.0) as u8,
                channel: 0,
            });
        }
    }
    notes.sort_by(|a, b| a.onset_s.total_cmp(&b.onset_s).then(b.midi.cmp(&a.midi)));
    Ok(notes)
}

/// The score of the corpus item in `dir` (module docs).
pub fn item_midi_score(dir: &Path) -> Result<MidiScore> {
    let notes = item_notes(dir)?;
    let beats_s = read_first_column(&dir.join("beats.txt"))?;
    let downbeats_s = read_first_column(&dir.join("downbeats.txt"))?;
    let labels_path = dir.join("labels.json");
    let labels: serde_json::Value = std::fs::read_to_string(&labels_path)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .ok_or_else(|| bad(&labels_path, "missing or not JSON"))?;
    let (bar, tempo) = notated_meter(dir);
    let compound = labels["beat_quarters"]
        .as_f64()
        .is_some_and(|q| (q - 1.5).abs() < 1e-6);
    let duration_s = notes.iter().map(|n| n.offset_s).fold(0.0, f64::max) + 0.5;
    Ok(MidiScore {
        notes,
        beats_s,
        downbeats_s,
        meter: Meter {
            beats_per_bar: bar.unwrap_or(4),
            subdivisions: if compound { 3 } else { 2 },
        },
        meter_from_file: true,
        tempo_bpm: tempo.unwrap_or(120.0),
        duration_s,
        transposed: 0,
    })
}
