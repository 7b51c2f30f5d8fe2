//! The 15-line use of the facade: a recording of any length in, motion JSON and an HTML
//! player (skeleton and audio in sync) out.
//!
//! `cargo run --release --example generate -- take1.wav out.json`

use violin_skeleton::skeleton_render::{audio_mime, write_html_player_file};
use violin_skeleton::{MotionFormat, Pipeline};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(input), Some(output)) = (args.get(1), args.get(2)) else {
        return Err("usage: generate IN.wav OUT.json".into());
    };
    let pipeline = Pipeline::default();
    // Decoded and analysed a piece at a time: memory stays flat for long recordings.
    let analysis = pipeline.analyze_file(input, |done_s, _| eprint!("\r{done_s:.0} s"))?;
    println!(
        "\n{} notes, {} bow changes, {:.0} bpm",
        analysis.notes.len(),
        analysis.bow_changes_s.len(),
        analysis.tempo_bpm
    );
    let motion = pipeline.generate_from_analysis(&analysis)?;
    motion.write(output, MotionFormat::Json)?;
    let audio = std::fs::read(input)?;
    let mime = audio_mime(input.as_ref()).unwrap_or("audio/wav");
    write_html_player_file(&motion, Some((&audio, mime)), format!("{output}.html"))?;
    println!(
        "{} frames written to {output} and {output}.html",
        motion.len()
    );
    Ok(())
}
