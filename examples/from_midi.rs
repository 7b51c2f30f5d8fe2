//! MIDI in, motion out: notes and timing from the file, bowing from slur/articulation
//! heuristics, arousal from velocity.
//!
//! `cargo run --release --example from_midi -- piece.mid piece.bvh`

use violin_skeleton::{MotionFormat, Pipeline};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (input, output) = match (args.get(1), args.get(2)) {
        (Some(i), Some(o)) => (i, o),
        _ => return Err("usage: from_midi IN.mid OUT.json".into()),
    };
    let pipeline = Pipeline::default();
    let perf = pipeline.performance_from_midi(input)?;
    println!(
        "{} notes, {} bow strokes, {} downbeats",
        perf.notes().len(),
        perf.bow_changes_s().len(),
        perf.downbeats_s().len()
    );
    let motion = pipeline.generate_midi(input)?;
    motion.write(output, MotionFormat::Json)?;
    println!("{} frames written to {output}", motion.len());
    Ok(())
}
