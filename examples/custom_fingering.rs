//! Choosing the fingering: the original greedy rule vs the optimal planner with custom
//! weights (no open strings, shifts expensive), then synthesising the same passage both ways.
//!
//! `cargo run --release --example custom_fingering`

use violin_skeleton::fingering::{CostWeights, FingeringPlanner, GreedyPlanner, OptimalPlanner};
use violin_skeleton::motion_synth::{synthesize, SynthConfig};
use violin_skeleton::Performance;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // A D major scale, D4 to D6, one note every 0.4 s.
    let scale: Vec<u8> = [62, 64, 66, 67, 69, 71, 73, 74, 76, 78, 79, 81, 83, 85, 86].into();
    let greedy = GreedyPlanner::default().plan(&scale[..13])?; // the original table stops at E6
    let weights = CostWeights {
        forbid_open_strings: true,
        shift: 2.0,
        ..CostWeights::default()
    };
    let optimal = OptimalPlanner::with_weights(weights).plan(&scale)?;
    for (i, m) in scale.iter().enumerate() {
        let g = greedy.get(i).map_or("-".to_string(), |f| {
            format!("{}-{}-{}", f.string.number(), f.position, f.finger)
        });
        let o = &optimal[i];
        println!(
            "midi {m}: greedy {g:>7}   optimal {}-{}-{}",
            o.string.number(),
            o.position,
            o.finger
        );
    }
    let mut builder = Performance::builder(0.4 * scale.len() as f64 + 0.5);
    for (i, (m, f)) in scale.iter().zip(&optimal).enumerate() {
        let t = 0.4 * i as f64;
        builder = builder.fingered_note(t, t + 0.38, *m, *f);
    }
    let perf = builder
        .bow_changes((1..scale.len()).map(|i| 0.4 * i as f64).collect())
        .build()?;
    let motion = synthesize(&perf, &SynthConfig::default())?;
    println!(
        "{} frames; left-wrist jitter {:.2} px/frame²",
        motion.len(),
        motion.jitter_per_joint()[7]
    );
    Ok(())
}
