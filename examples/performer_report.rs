//! The whole performer's figures on a recording: bow–string and fingertip–string contact,
//! hand jitter, bone-length CV, core jitter (issue #25's goals), through the same analysis
//! and synthesis `generate` runs.
//!
//! ```sh
//! cargo run --release --example performer_report -- take.wav
//! ```

use violin_skeleton::motion_synth::metrics::MotionReport;
use violin_skeleton::motion_synth::synthesize_detailed;
use violin_skeleton::{load_audio, Pipeline};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: performer_report AUDIO");
        std::process::exit(2);
    };
    let audio = load_audio(&path)?;
    let pipeline = Pipeline::default();
    let analysis = pipeline.analyze(&audio)?;
    let perf = pipeline.performance(&analysis)?;
    let out = synthesize_detailed(&perf, pipeline.synth_config())?;
    let report = MotionReport::measure(&out, &perf);
    println!("{path}: {}", serde_json::to_string_pretty(&report)?);
    Ok(())
}
