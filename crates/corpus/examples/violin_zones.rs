//! Lists the samples a violin source plays — per key range its root key, sample rate,
//! length and loop length — so that sample sets can be compared (two sources built from the
//! same recordings show the same roots, lengths and loops; `crates/corpus/DATA_SOURCES.md`
//! checks a new source against the held-out and reserved ones this way).
//!
//! ```text
//! cargo run --release -p corpus --example violin_zones -- /usr/share/sounds/sf2/TimGM6mb.sf2:40 0400_JCLive_sf2_file.js 040_Violin.pat
//! ```
//! An SF2 takes its GM program after a colon (40 when none); `.pat` is a GUS patch, `.js` a
//! WebAudioFont instrument.
#![allow(clippy::print_stdout)]

use std::path::Path;

use corpus::render::{gus_patch_samples, webaudiofont_samples, write_sf2};

fn sf2_bytes(arg: &str) -> Result<(Vec<u8>, i32), Box<dyn std::error::Error>> {
    let (file, program) = match arg.rsplit_once(':') {
        Some((f, p)) if p.chars().all(|c| c.is_ascii_digit()) => (f, p.parse()?),
        _ => (arg, 40),
    };
    let ext = Path::new(file)
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("");
    let bytes = std::fs::read(file).map_err(|e| format!("{file}: {e}"))?;
    Ok(match ext {
        "pat" => (write_sf2(b"GUS patch", 40, &gus_patch_samples(&bytes)?), 40),
        "js" => (
            write_sf2(
                b"WebAudioFont",
                40,
                &webaudiofont_samples(std::str::from_utf8(&bytes)?)?,
            ),
            40,
        ),
        _ => (bytes, program),
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.is_empty() {
        return Err("usage: violin_zones SOURCE[:PROGRAM]...".into());
    }
    for arg in &args {
        let (bytes, program) = sf2_bytes(arg)?;
        let font = rustysynth::SoundFont::new(&mut &bytes[..])
            .map_err(|e| format!("{arg}: not a usable SF2 ({e:?})"))?;
        let preset = font
            .get_presets()
            .iter()
            .find(|p| p.get_patch_number() == program && p.get_bank_number() == 0)
            .ok_or_else(|| format!("{arg}: no GM program {program} in bank 0"))?;
        println!("{arg}: preset {:?}", preset.get_name());
        println!("  keys     root  cents  rate_hz  length_s  loop_s");
        for pr in preset.get_regions() {
            let Some(inst) = font.get_instruments().get(pr.get_instrument_id()) else {
                continue;
            };
            for r in inst.get_regions() {
                let Some(h) = font.get_sample_headers().get(r.get_sample_id()) else {
                    continue;
                };
                let rate = f64::from(h.get_sample_rate().max(1));
                println!(
                    "  {:>3}-{:<3}  {:>4}  {:>5}  {:>7}  {:>8.3}  {:>6.3}",
                    r.get_key_range_start(),
                    r.get_key_range_end(),
                    r.get_root_key(),
                    r.get_fine_tune() + 100 * r.get_coarse_tune(),
                    h.get_sample_rate(),
                    f64::from(h.get_end() - h.get_start()) / rate,
                    f64::from(h.get_end_loop() - h.get_start_loop()) / rate,
                );
            }
        }
    }
    Ok(())
}
