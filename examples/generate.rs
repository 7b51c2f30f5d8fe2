//! The 15-line use of the facade: a recording in, motion JSON and an HTML player out.
//!
//! `cargo run --release --example generate -- take1.wav out.json`

use violin_skeleton::{load_audio, MotionFormat, Pipeline};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (input, output) = match (args.get(1), args.get(2)) {
        (Some(i), Some(o)) => (i, o),
        _ => return Err("usage: generate IN.wav OUT.json".into()),
    };
    let audio = load_audio(input)?;
    let pipeline = Pipeline::default();
    let analysis = pipeline.analyze(&audio)?;
    println!(
        "{} notes, {} bow changes, {:.0} bpm",
        analysis.notes.len(),
        analysis.bow_changes_s.len(),
        analysis.tempo_bpm
    );
    let motion = pipeline.generate_from_analysis(&analysis)?;
    motion.write(output, MotionFormat::Json)?;
    println!("{} frames written to {output}", motion.len());
    Ok(())
}
