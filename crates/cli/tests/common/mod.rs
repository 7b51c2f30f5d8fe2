//! Inputs the CLI tests make: a WAV tone and a MIDI scale of any length.
#![allow(dead_code, clippy::unwrap_used)]

use std::path::Path;

/// A 22 050 Hz 16-bit WAV of a steady tone, `seconds` long.
pub fn write_wav(path: &Path, seconds: f64) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 22_050,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for i in 0..(seconds * 22_050.0) as usize {
        w.write_sample(((i as f32 * 0.125).sin() * 8000.0) as i16)
            .unwrap();
    }
    w.finalize().unwrap();
}

/// A 16-bit mono WAV of `samples` (in −1…1) at `rate`.
pub fn write_samples_wav(path: &Path, samples: &[f32], rate: u32) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for &s in samples {
        w.write_sample((s * 32_000.0) as i16).unwrap();
    }
    w.finalize().unwrap();
}

/// A format-0 MIDI file: `notes` quarter notes at 120 bpm (0.5 s each), a G major scale.
pub fn write_midi(path: &Path, notes: usize) {
    let mut track = vec![0x00, 0xFF, 0x51, 0x03, 0x07, 0xA1, 0x20];
    for k in 0..notes {
        let key = [67u8, 69, 71, 72, 74, 76, 78, 79][k % 8];
        track.extend_from_slice(&[0x00, 0x90, key, 80, 0x83, 0x60, 0x80, key, 0x40]);
    }
    track.extend_from_slice(&[0x00, 0xFF, 0x2F, 0x00]);
    let mut smf = b"MThd\x00\x00\x00\x06\x00\x00\x00\x01\x01\xE0MTrk".to_vec();
    smf.extend_from_slice(&(track.len() as u32).to_be_bytes());
    smf.extend_from_slice(&track);
    std::fs::write(path, smf).unwrap();
}
