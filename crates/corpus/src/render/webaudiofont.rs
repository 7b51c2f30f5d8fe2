//! A WebAudioFont instrument (`.js`, github.com/surikov/webaudiofontdata: SoundFont
//! instruments converted for the browser) read into an SF2 the [`SoundFontRenderer`] plays.
//!
//! Such a file is one JavaScript object whose `zones` each hold a sample — an MP3 in base64
//! (`file`) or base64 16-bit little-endian PCM (`sample`) — with the SoundFont zone's key
//! range, root pitch (`originalPitch` in cents, less `coarseTune` semitones and `fineTune`
//! cents), loop points and sample rate. The MP3s are coded at a standard rate while the loop
//! points count samples at the zone's own rate, so loop points are rescaled to the decoded
//! rate, then moved to the nearest rising zero crossings inside the loop (an MP3's loop seam
//! is not sample-exact, and a click every loop would sound like a bow change).

use std::path::Path;

use base64::Engine as _;

use crate::render::renderer::RenderError;
use crate::render::sample_dir::steady_middle;
use crate::render::sf2_writer::{write_sf2, Sf2Sample};
use crate::render::SoundFontRenderer;

/// The longest sample kept per zone, s.
const MAX_ZONE_S: f64 = 12.0;

/// One zone's fields as written in the file (numbers, booleans and quoted strings at the
/// zone's top level; nested arrays and objects such as an `ahdsr` envelope are skipped).
#[derive(Debug, Default)]
struct RawZone {
    fields: Vec<(String, String)>,
}

impl RawZone {
    fn text(&self, key: &str) -> Option<&str> {
        self.fields
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    fn number(&self, key: &str) -> Result<f64, RenderError> {
        let v = self
            .text(key)
            .ok_or_else(|| RenderError::SoundFont(format!("a zone has no `{key}`")))?;
        v.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| RenderError::SoundFont(format!("a zone's `{key}` is not a number: {v}")))
    }
}

/// The end (exclusive) of the bracketed group opening at `start` (`{` or `[`), skipping
/// quoted strings.
fn group_end(bytes: &[u8], start: usize) -> Option<usize> {
    let mut depth = 0usize;
    let mut quote: Option<u8> = None;
    for (i, &b) in bytes.iter().enumerate().skip(start) {
        match (quote, b) {
            (Some(q), _) if b == q => quote = None,
            (Some(_), _) => {}
            (None, b'\'' | b'"') => quote = Some(b),
            (None, b'{' | b'[') => depth += 1,
            (None, b'}' | b']') => {
                depth = depth.checked_sub(1)?;
                if depth == 0 {
                    return Some(i + 1);
                }
            }
            _ => {}
        }
    }
    None
}

/// The top-level `key: value` fields of the object text `body` (without its braces).
fn fields(body: &str) -> Vec<(String, String)> {
    let bytes = body.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let Some(colon) = body[i..].find(':').map(|c| i + c) else {
            break;
        };
        let key = body[i..colon]
            .trim_matches(|c: char| c.is_whitespace() || c == ',' || c == '"' || c == '\'')
            .to_string();
        let mut j = colon + 1;
        while j < bytes.len() && bytes[j].is_ascii_whitespace() {
            j += 1;
        }
        let (value, next) = match bytes.get(j) {
            Some(&q @ (b'\'' | b'"')) => match body[j + 1..].find(q as char) {
                Some(len) => (body[j + 1..j + 1 + len].to_string(), j + len + 2),
                None => break,
            },
            Some(b'{' | b'[') => match group_end(bytes, j) {
                Some(end) => (String::new(), end),
                None => break,
            },
            _ => {
                let end = body[j..].find(',').map_or(bytes.len(), |c| j + c);
                (body[j..end].trim().to_string(), end)
            }
        };
        out.push((key, value));
        i = next;
    }
    out
}

/// The zones of a WebAudioFont file's text.
fn raw_zones(text: &str) -> Result<Vec<RawZone>, RenderError> {
    let bytes = text.as_bytes();
    let start = text
        .find("zones")
        .and_then(|z| text[z..].find('[').map(|b| z + b))
        .ok_or_else(|| RenderError::SoundFont("no `zones:[…]` list (not a WebAudioFont)".into()))?;
    let end = group_end(bytes, start)
        .ok_or_else(|| RenderError::SoundFont("the `zones` list is not closed".into()))?;
    let mut zones = Vec::new();
    let mut i = start + 1;
    while let Some(open) = text[i..end].find('{').map(|o| i + o) {
        let close = group_end(bytes, open)
            .filter(|&c| c <= end)
            .ok_or_else(|| RenderError::SoundFont("a zone is not closed".into()))?;
        zones.push(RawZone {
            fields: fields(&text[open + 1..close - 1]),
        });
        i = close;
    }
    if zones.is_empty() {
        return Err(RenderError::SoundFont("the `zones` list is empty".into()));
    }
    Ok(zones)
}

/// A zone's sound as 16-bit samples and their rate.
fn zone_audio(zone: &RawZone, index: usize) -> Result<(Vec<i16>, u32), RenderError> {
    let decode = |b64: &str| {
        base64::engine::general_purpose::STANDARD
            .decode(b64.trim())
            .map_err(|e| RenderError::SoundFont(format!("zone {index}: bad base64 ({e})")))
    };
    let zone_rate = zone.number("sampleRate")?;
    if let Some(file) = zone.text("file") {
        let bytes = decode(file)?;
        let label = format!("zone {index}'s sound");
        let audio = dsp_mel::load_audio_bytes(bytes, Path::new(&label), None)
            .map_err(|e| RenderError::SoundFont(format!("zone {index}: {e}")))?;
        let data = audio
            .samples()
            .iter()
            .map(|v| (v.clamp(-1.0, 1.0) * 32_767.0) as i16)
            .collect();
        return Ok((data, audio.sample_rate_hz()));
    }
    let pcm = zone
        .text("sample")
        .ok_or_else(|| RenderError::SoundFont(format!("zone {index} has no `file` or `sample`")))?;
    let bytes = decode(pcm)?;
    let data = bytes
        .chunks_exact(2)
        .map(|p| i16::from_le_bytes([p[0], p[1]]))
        .collect();
    if !(1_000.0..=192_000.0).contains(&zone_rate) {
        return Err(RenderError::SoundFont(format!(
            "zone {index}: sample rate {zone_rate} Hz"
        )));
    }
    Ok((data, zone_rate as u32))
}

/// The rising zero crossing nearest to `target` inside `lo..hi`, or `target` when none.
fn rising_zero_near(data: &[i16], target: usize, lo: usize, hi: usize) -> usize {
    let rising = |i: usize| i > 0 && i < data.len() && data[i - 1] < 0 && data[i] >= 0;
    (0..hi.saturating_sub(lo))
        .flat_map(|d| [target.checked_sub(d), target.checked_add(d)])
        .flatten()
        .find(|&i| i >= lo && i < hi && rising(i))
        .unwrap_or(target)
}

/// One zone as an [`Sf2Sample`].
fn zone_sample(zone: &RawZone, index: usize) -> Result<Sf2Sample, RenderError> {
    let (mut data, rate_hz) = zone_audio(zone, index)?;
    data.truncate((MAX_ZONE_S * f64::from(rate_hz)) as usize);
    if data.len() < 64 || data.iter().all(|&v| v == 0) {
        return Err(RenderError::SoundFont(format!(
            "zone {index}: silent or shorter than 64 samples"
        )));
    }
    let cents = zone.number("originalPitch")?
        - 100.0 * zone.number("coarseTune").unwrap_or(0.0)
        - zone.number("fineTune").unwrap_or(0.0);
    let root_key = (cents / 100.0).round().clamp(0.0, 127.0);
    let correction = (root_key * 100.0 - cents).round().clamp(-50.0, 50.0);
    let key = |name: &str, default: f64| {
        zone.number(name)
            .unwrap_or(default)
            .round()
            .clamp(0.0, 127.0) as u8
    };
    let scale = f64::from(rate_hz) / zone.number("sampleRate")?;
    let len = data.len();
    let at = |name: &str| {
        zone.number(name)
            .ok()
            .filter(|v| *v >= 0.0)
            .map(|v| ((v * scale).round() as usize).min(len))
    };
    let (start, end) = match (at("loopStart"), at("loopEnd")) {
        (Some(s), Some(e)) if e > s + 16 => (s, e),
        // No loop: hold the sound's steady middle, as a folder of recordings is.
        _ => steady_middle(len),
    };
    let quarter = (end - start) / 4;
    let loop_start = rising_zero_near(&data, start, start, start + quarter);
    let loop_end = rising_zero_near(&data, end, end.saturating_sub(quarter), end + 1);
    let (loop_start, loop_end) = if loop_end > loop_start + 8 {
        (loop_start, loop_end)
    } else {
        (start, end)
    };
    Ok(Sf2Sample {
        data,
        rate_hz,
        root_key: root_key as u8,
        pitch_correction_cents: correction as i8,
        loop_start: loop_start as u32,
        loop_end: loop_end as u32,
        key_lo: key("keyRangeLow", 0.0),
        key_hi: key("keyRangeHigh", 127.0),
    })
}

/// The zones of the WebAudioFont text `text` as looped [`Sf2Sample`]s, lowest key range
/// first, overlapping ranges trimmed so that each key plays one zone.
pub fn webaudiofont_samples(text: &str) -> Result<Vec<Sf2Sample>, RenderError> {
    let mut samples = raw_zones(text)?
        .iter()
        .enumerate()
        .map(|(i, z)| zone_sample(z, i + 1))
        .collect::<Result<Vec<_>, _>>()?;
    samples.retain(|s| s.key_lo <= s.key_hi);
    samples.sort_by_key(|s| (s.key_lo, s.key_hi));
    let mut next_lo = 0u8;
    let mut kept = Vec::with_capacity(samples.len());
    for mut s in samples {
        if !kept.is_empty() {
            if s.key_hi < next_lo {
                continue;
            }
            s.key_lo = s.key_lo.max(next_lo);
        }
        next_lo = s.key_hi.saturating_add(1);
        let full = s.key_hi == 127;
        kept.push(s);
        if full {
            break;
        }
    }
    Ok(kept)
}

impl SoundFontRenderer {
    /// A renderer playing the WebAudioFont instrument (`.js`) at `path` as GM program 40
    /// (module `webaudiofont`); errors name the file.
    pub fn from_webaudiofont_file(path: impl AsRef<Path>) -> Result<Self, RenderError> {
        Self::from_file_with(path.as_ref(), |bytes| {
            let text = std::str::from_utf8(bytes)
                .map_err(|_| RenderError::SoundFont("not UTF-8 text".into()))?;
            Self::from_bytes(&write_sf2(
                b"WebAudioFont",
                40,
                &webaudiofont_samples(text)?,
            ))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` samples of a `hz` sine at `rate` as 16-bit values.
    fn sine(hz: f64, rate: u32, n: usize) -> Vec<i16> {
        (0..n)
            .map(|i| {
                ((std::f64::consts::TAU * hz * i as f64 / f64::from(rate)).sin() * 12_000.0) as i16
            })
            .collect()
    }

    fn b64(bytes: &[u8]) -> String {
        base64::engine::general_purpose::STANDARD.encode(bytes)
    }

    /// A WAV file (as a WebAudioFont `file` would hold an MP3) of `data` at `rate`.
    fn wav(data: &[i16], rate: u32) -> Vec<u8> {
        let spec = hound::WavSpec {
            channels: 1,
            sample_rate: rate,
            bits_per_sample: 16,
            sample_format: hound::SampleFormat::Int,
        };
        let mut cursor = std::io::Cursor::new(Vec::new());
        let mut w = hound::WavWriter::new(&mut cursor, spec).unwrap();
        for &v in data {
            w.write_sample(v).unwrap();
        }
        w.finalize().unwrap();
        cursor.into_inner()
    }

    /// Two zones: a coded file at 24 kHz whose loop points count 48 kHz samples, with an
    /// envelope array to skip, and raw PCM overlapping its key range.
    fn font() -> String {
        let low = wav(&sine(196.0, 24_000, 24_000), 24_000);
        let pcm: Vec<u8> = sine(440.0, 22_050, 22_050)
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        format!(
            "console.log('load');\nvar _tone_0400_test={{\n\tzones:[\n\t\t{{\n\t\t\tmidi:40\n\t\t\t,originalPitch:5500\n\t\t\t,keyRangeLow:0\n\t\t\t,keyRangeHigh:62\n\t\t\t,loopStart:20000\n\t\t\t,loopEnd:40000\n\t\t\t,coarseTune:0\n\t\t\t,fineTune:-20\n\t\t\t,sampleRate:48000\n\t\t\t,ahdsr:[{{duration:0,volume:1}},{{duration:0.5,volume:0.5}}]\n\t\t\t,file:'{}'\n\t\t}},\n\t\t{{\n\t\t\tmidi:40\n\t\t\t,originalPitch:6900\n\t\t\t,keyRangeLow:60\n\t\t\t,keyRangeHigh:127\n\t\t\t,loopStart:-1\n\t\t\t,loopEnd:-2\n\t\t\t,coarseTune:0\n\t\t\t,fineTune:0\n\t\t\t,sampleRate:22050\n\t\t\t,ahdsr:false\n\t\t\t,sample:'{}'\n\t\t}}\n\t]\n}};\n",
            b64(&low),
            b64(&pcm)
        )
    }

    #[test]
    fn zones_read_with_pitch_loops_and_key_ranges() {
        let s = webaudiofont_samples(&font()).unwrap();
        assert_eq!(s.len(), 2);
        // 5500 cents less a fine tune of −20: the sample sounds at 55.2, so root 55, −20 cents.
        assert_eq!((s[0].root_key, s[0].pitch_correction_cents), (55, -20));
        assert_eq!((s[0].rate_hz, s[0].data.len()), (24_000, 24_000));
        // Loop points at 48 kHz halved, then moved onto rising zero crossings near them.
        assert!((10_000..10_000 + 130).contains(&(s[0].loop_start as usize)));
        assert!((20_000 - 130..=20_000).contains(&(s[0].loop_end as usize)));
        let (ls, le) = (s[0].loop_start as usize, s[0].loop_end as usize);
        assert!(s[0].data[ls - 1] < 0 && s[0].data[ls] >= 0);
        assert!(s[0].data[le - 1] < 0 && s[0].data[le] >= 0);
        // Overlapping ranges trimmed: 0–62, then 63–127.
        assert_eq!(
            (s[0].key_lo, s[0].key_hi, s[1].key_lo, s[1].key_hi),
            (0, 62, 63, 127)
        );
        // The unlooped PCM zone loops over its middle, as a folder of recordings does.
        assert_eq!((s[1].root_key, s[1].rate_hz), (69, 22_050));
        assert!(s[1].loop_start as usize >= 22_050 / 2 && (s[1].loop_end as usize) <= 22_050);
    }

    #[test]
    fn a_file_becomes_a_violin_renderer() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("0400_test.js");
        std::fs::write(&path, font()).unwrap();
        let r = SoundFontRenderer::from_webaudiofont_file(&path).unwrap();
        assert!(r.has_program(40));
    }

    #[test]
    fn bad_files_are_refused_with_the_reason() {
        let err = |t: &str| webaudiofont_samples(t).unwrap_err().to_string();
        assert!(err("var x = 1;").contains("no `zones"));
        assert!(err("zones:[ {midi:40").contains("not closed"));
        assert!(err("zones:[]").contains("empty"));
        let good = font();
        assert!(
            err(&good.replace("originalPitch:5500", "originalPitch:x")).contains("originalPitch")
        );
        assert!(err(&good.replacen("file:'", "file:'@@", 1)).contains("base64"));
        assert!(err(&good.replacen(",sampleRate:48000", "", 1)).contains("sampleRate"));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing.js");
        let e = SoundFontRenderer::from_webaudiofont_file(&path).unwrap_err();
        assert!(e.to_string().contains("missing.js"));
    }
}
