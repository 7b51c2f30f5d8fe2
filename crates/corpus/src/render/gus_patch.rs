//! Gravis UltraSound patches (`.pat`, "GF1PATCH110", as FreePats ships them) read into an
//! SF2 the [`SoundFontRenderer`] plays: every sample of the patch's first layer, looped as
//! the patch loops it, over the key range its frequency range covers, at its root pitch.
//! The patch's envelope and tremolo/vibrato settings are not carried over (the renderer
//! makes its own vibrato); 16- and 8-bit, signed and unsigned samples are read.

use std::path::Path;

use crate::render::renderer::RenderError;
use crate::render::sf2_writer::{write_sf2, Sf2Sample};
use crate::render::SoundFontRenderer;

const HEADER: usize = 129;
const INSTRUMENT: usize = 63;
const LAYER: usize = 47;
const SAMPLE: usize = 96;

fn bad(reason: impl Into<String>) -> RenderError {
    RenderError::SoundFont(format!("not a usable GUS patch: {}", reason.into()))
}

fn u16_at(b: &[u8], at: usize) -> Result<u16, RenderError> {
    b.get(at..at + 2)
        .map(|s| u16::from_le_bytes([s[0], s[1]]))
        .ok_or_else(|| bad("truncated"))
}

fn u32_at(b: &[u8], at: usize) -> Result<u32, RenderError> {
    b.get(at..at + 4)
        .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
        .ok_or_else(|| bad("truncated"))
}

/// MIDI key (fractional) of a frequency in millihertz.
fn key_of_mhz(mhz: u32) -> f64 {
    69.0 + 12.0 * (f64::from(mhz.max(1)) / 440_000.0).log2()
}

/// The samples of a GUS patch as [`Sf2Sample`]s, lowest first, with key ranges that cover
/// every key without gaps.
pub fn gus_patch_samples(bytes: &[u8]) -> Result<Vec<Sf2Sample>, RenderError> {
    if !bytes.starts_with(b"GF1PATCH1") {
        return Err(bad("no GF1PATCH header"));
    }
    let layer = HEADER + INSTRUMENT;
    let count = usize::from(*bytes.get(layer + 6).ok_or_else(|| bad("truncated"))?);
    if count == 0 {
        return Err(bad("no samples"));
    }
    let mut at = layer + LAYER;
    let mut samples: Vec<(f64, f64, Sf2Sample)> = Vec::with_capacity(count);
    for k in 0..count {
        let h = at;
        let len = u32_at(bytes, h + 8)? as usize;
        let (loop_start, loop_end) = (u32_at(bytes, h + 12)?, u32_at(bytes, h + 16)?);
        let rate = u32::from(u16_at(bytes, h + 20)?);
        let (low, high, root) = (
            u32_at(bytes, h + 22)?,
            u32_at(bytes, h + 26)?,
            u32_at(bytes, h + 30)?,
        );
        let modes = *bytes.get(h + 55).ok_or_else(|| bad("truncated"))?;
        let data = bytes
            .get(h + SAMPLE..h + SAMPLE + len)
            .ok_or_else(|| bad(format!("sample {k}: {len} bytes announced, fewer present")))?;
        let (wide, unsigned) = (modes & 1 != 0, modes & 2 != 0);
        let pcm: Vec<i16> = if wide {
            data.chunks_exact(2)
                .map(|c| {
                    let v = u16::from_le_bytes([c[0], c[1]]);
                    if unsigned {
                        (i32::from(v) - 32768) as i16
                    } else {
                        v as i16
                    }
                })
                .collect()
        } else {
            data.iter()
                .map(|&v| {
                    let s = if unsigned {
                        i16::from(v) - 128
                    } else {
                        i16::from(v as i8)
                    };
                    s * 256
                })
                .collect()
        };
        let per = if wide { 2 } else { 1 };
        if rate == 0 || pcm.is_empty() {
            return Err(bad(format!(
                "sample {k}: rate {rate} Hz, {} samples",
                pcm.len()
            )));
        }
        let root_key = key_of_mhz(root);
        let key = root_key.round().clamp(0.0, 127.0);
        let looped = modes & 4 != 0 && loop_end > loop_start;
        let n = pcm.len() as u32;
        samples.push((
            key_of_mhz(low),
            key_of_mhz(high),
            Sf2Sample {
                loop_start: if looped {
                    loop_start / per
                } else {
                    n.saturating_sub(2)
                },
                loop_end: if looped { (loop_end / per).min(n) } else { n },
                data: pcm,
                rate_hz: rate,
                root_key: key as u8,
                pitch_correction_cents: ((key - root_key) * 100.0).round().clamp(-50.0, 50.0) as i8,
                key_lo: 0,
                key_hi: 127,
            },
        ));
        at = h + SAMPLE + len;
    }
    samples.sort_by(|a, b| a.0.total_cmp(&b.0));
    let last = samples.len() - 1;
    let mut next_lo = 0u8;
    let mut out = Vec::with_capacity(samples.len());
    for (i, (_, high, mut s)) in samples.into_iter().enumerate() {
        let hi = if i == last {
            127
        } else {
            (high.round().clamp(0.0, 127.0) as u8).max(next_lo)
        };
        s.key_lo = next_lo;
        s.key_hi = hi;
        next_lo = hi.saturating_add(1);
        out.push(s);
        if hi == 127 {
            break;
        }
    }
    Ok(out)
}

/// An SF2 (GM program 40) playing the samples of GUS patch `bytes`.
pub fn sf2_from_gus_patch(bytes: &[u8]) -> Result<Vec<u8>, RenderError> {
    Ok(write_sf2(b"GUS patch", 40, &gus_patch_samples(bytes)?))
}

impl SoundFontRenderer {
    /// A renderer playing the GUS patch (`.pat`) at `path` (module `gus_patch`).
    pub fn from_gus_patch_file(path: impl AsRef<Path>) -> Result<Self, RenderError> {
        Self::from_file_with(path.as_ref(), |bytes| {
            Self::from_bytes(&sf2_from_gus_patch(bytes)?)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A patch with one 16-bit signed, looped sample of a 220 Hz sine at 22 050 Hz.
    fn patch(len_bytes_announced: Option<u32>) -> Vec<u8> {
        let n = 2205usize;
        let data: Vec<u8> = (0..n)
            .flat_map(|i| {
                let v = (std::f64::consts::TAU * 220.0 * i as f64 / 22_050.0).sin() * 12_000.0;
                (v as i16).to_le_bytes()
            })
            .collect();
        let mut b = b"GF1PATCH110\0ID#000002\0".to_vec();
        b.resize(HEADER, 0);
        b.resize(HEADER + INSTRUMENT, 0);
        let mut layer = vec![0u8; LAYER];
        layer[6] = 1;
        b.extend(layer);
        let mut h = vec![0u8; SAMPLE];
        let len = len_bytes_announced.unwrap_or(data.len() as u32);
        h[8..12].copy_from_slice(&len.to_le_bytes());
        h[12..16].copy_from_slice(&200u32.to_le_bytes());
        h[16..20].copy_from_slice(&(data.len() as u32 - 200).to_le_bytes());
        h[20..22].copy_from_slice(&22_050u16.to_le_bytes());
        h[22..26].copy_from_slice(&100_000u32.to_le_bytes());
        h[26..30].copy_from_slice(&8_000_000u32.to_le_bytes());
        h[30..34].copy_from_slice(&220_000u32.to_le_bytes());
        h[55] = 0b0000_0101; // 16-bit, signed, looping
        b.extend(h);
        b.extend(data);
        b
    }

    #[test]
    fn a_patch_reads_as_one_looped_sample_over_every_key() {
        let s = gus_patch_samples(&patch(None)).unwrap();
        assert_eq!(s.len(), 1);
        assert_eq!((s[0].key_lo, s[0].key_hi, s[0].root_key), (0, 127, 57));
        assert_eq!((s[0].loop_start, s[0].loop_end), (100, 2205 - 100));
        assert_eq!(s[0].data.len(), 2205);
        let sf2 = sf2_from_gus_patch(&patch(None)).unwrap();
        let r = SoundFontRenderer::from_bytes(&sf2).unwrap();
        assert!(r.has_program(40));
    }

    #[test]
    fn truncated_and_foreign_files_are_refused() {
        let e = gus_patch_samples(&patch(Some(1_000_000))).unwrap_err();
        assert!(e.to_string().contains("fewer present"), "{e}");
        assert!(gus_patch_samples(b"RIFF....").is_err());
        assert!(gus_patch_samples(&patch(None)[..150]).is_err());
    }
}
