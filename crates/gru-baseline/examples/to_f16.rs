//! Converts a Method 1 weights file to half precision (how the shipped weights were made:
//! about half the size, outputs within ~1e-3 of the f32 file), keeping its training record.
//!
//! `cargo run --release -p gru-baseline --example to_f16 -- IN.safetensors OUT.safetensors`
#![allow(clippy::unwrap_used, clippy::expect_used)]

use gru_baseline::{GruBaseline, StorageDtype};

fn main() -> Result<(), gru_baseline::GruError> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = args.as_slice() else {
        eprintln!("usage: to_f16 IN.safetensors OUT.safetensors");
        std::process::exit(2);
    };
    let (net, record) = GruBaseline::load_with_record(input)?;
    net.save(output, StorageDtype::F16, record.as_ref())?;
    let half = GruBaseline::load(output)?;
    let mel =
        ndarray::Array2::from_shape_fn((900, 128), |(t, b)| -60.0 + ((t * 7 + b * 13) % 50) as f32);
    let a = net.predict_mel(mel.view())?;
    let b = half.predict_mel(mel.view())?;
    let max_px = (a.frames() - b.frames())
        .mapv(f32::abs)
        .iter()
        .cloned()
        .fold(0.0, f32::max);
    println!(
        "{output}: {} bytes (from {}), max joint difference on 30 s of test mel {max_px:.4} px",
        std::fs::metadata(output).map(|m| m.len()).unwrap_or(0),
        std::fs::metadata(input).map(|m| m.len()).unwrap_or(0)
    );
    Ok(())
}
