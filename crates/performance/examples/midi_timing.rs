//! Times the library side of `violin-skeleton analyze X.mid`: reading the score (every
//! note, beats, bars), the melodic line with its bowing, stroke directions and the learned
//! fingering of every note. `cargo run --release -p performance --features midi --example
//! midi_timing -- X.mid`
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Instant;

use fingering::{FingeringPlanner, LearnedPlanner};
use performance::midi::{score_from_midi_file, timeline_from_score, MidiOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).ok_or("usage: midi_timing X.mid")?;
    for run in 0..5 {
        let t = Instant::now();
        // As the facade does: the planner (parsing its embedded parameters) per analysis.
        let planner = LearnedPlanner::default();
        let setup = t.elapsed();
        let score = score_from_midi_file(&path, &MidiOptions::default())?;
        let read = t.elapsed();
        let timeline = timeline_from_score(&score);
        let notes: Vec<performance::Note> = timeline.notes.iter().map(|n| n.note).collect();
        let changes = timeline.bow_changes_s();
        let dirs = performance::bow_directions(&changes, &notes, &score.downbeats_s);
        let midi: Vec<u8> = score.notes.iter().map(|n| n.midi).collect();
        let t_plan = Instant::now();
        let plan = planner.plan(&midi)?;
        println!(
            "run {run}: {} notes, {:.1} s, {} beats, {} strokes ({}): planner setup {:.2} ms, read {:.2} ms, plan {:.2} ms, total {:.2} ms",
            score.notes.len(),
            score.duration_s,
            score.beats_s.len(),
            changes.len(),
            dirs.len(),
            setup.as_secs_f64() * 1e3,
            (read - setup).as_secs_f64() * 1e3,
            t_plan.elapsed().as_secs_f64() * 1e3,
            t.elapsed().as_secs_f64() * 1e3
        );
        assert_eq!(plan.len(), midi.len());
    }
    Ok(())
}
