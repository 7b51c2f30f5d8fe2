//! Times the GLB export of a motion file: `cargo run --release -p skeleton --example
//! glb_timing -- motion.json out.glb` prints the node layout, the file size and the median
//! of five writes (node table → bytes → atomic file).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Instant;

use skeleton::formats::gltf::motion_animation;
use skeleton::{Motion, MotionFormat};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, input, output] = args.as_slice() else {
        eprintln!("usage: glb_timing MOTION.json OUT.glb");
        std::process::exit(2);
    };
    let motion = Motion::read(input, MotionFormat::from_path(input.as_ref())?)?;
    let anim = motion_animation(&motion)?;
    let mut times_ms: Vec<f64> = (0..5)
        .map(|_| {
            let t0 = Instant::now();
            motion
                .write(output, MotionFormat::Glb)
                .map(|()| t0.elapsed().as_secs_f64() * 1e3)
        })
        .collect::<Result<_, _>>()?;
    times_ms.sort_by(f64::total_cmp);
    println!(
        "{} frames ({:.1} s) × {} nodes → {} bytes; write median {:.1} ms (min {:.1}, max {:.1})",
        motion.len(),
        motion.duration_s(),
        anim.nodes().len(),
        std::fs::metadata(output)?.len(),
        times_ms[2],
        times_ms[0],
        times_ms[4]
    );
    Ok(())
}
