//! What the HTML player plays: audio embedded in the page, an audio file beside it, the
//! notes of a MIDI file synthesized in the browser, or nothing.

use std::fmt::Write as _;
use std::io::Write;

use base64::engine::general_purpose::STANDARD;
use base64::write::EncoderWriter;

use crate::error::{RenderError, Result};

/// One note for the player's in-browser synthesizer (Web Audio: a filtered sawtooth).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayerNote {
    /// Start, seconds.
    pub onset_s: f64,
    /// End, seconds.
    pub offset_s: f64,
    /// MIDI pitch (69 = A4; fractions allowed).
    pub midi: f32,
    /// Loudness 0..1.
    pub velocity: f32,
}

/// The sound of an HTML player page.
#[derive(Debug, Clone, Copy)]
pub enum PlayerSound<'a> {
    /// Silent: the player runs on its own clock.
    None,
    /// The audio file's bytes, embedded as a base64 data URI with its MIME type (e.g.
    /// `audio/wav`): one self-contained page, as large as the audio (× 4/3).
    Embedded {
        /// The file's bytes.
        bytes: &'a [u8],
        /// Its MIME type.
        mime: &'a str,
    },
    /// A reference to an audio file (a path relative to the page, or a URL): a small page
    /// that plays while the file stays where the reference says.
    Linked {
        /// The `src` of the `<audio>` element.
        src: &'a str,
    },
    /// Notes played by a small synthesizer in the browser (MIDI input), in time with the
    /// player's own clock.
    Notes(&'a [PlayerNote]),
}

fn check_mime(mime: &str) -> Result<()> {
    let ok_part = |s: &str| {
        !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
    };
    match mime.split_once('/') {
        Some((a, b)) if ok_part(a) && ok_part(b) => Ok(()),
        _ => Err(RenderError::InvalidMime(mime.to_string())),
    }
}

/// Escapes text for a double-quoted HTML attribute.
fn attribute(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '"' => out.push_str("&quot;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            _ => out.push(c),
        }
    }
    out
}

/// Checks what can be checked before anything is written.
pub(crate) fn validate(sound: &PlayerSound<'_>) -> Result<()> {
    match sound {
        PlayerSound::Embedded { mime, .. } => check_mime(mime),
        PlayerSound::Linked { src: "" } => Err(RenderError::InvalidConfig(
            "the linked audio's path is empty".into(),
        )),
        _ => Ok(()),
    }
}

/// Writes the page's sound element (or nothing).
pub(crate) fn write_sound(sound: &PlayerSound<'_>, out: &mut impl Write) -> Result<()> {
    match sound {
        PlayerSound::None => {}
        PlayerSound::Embedded { bytes, mime } => {
            write!(
                out,
                "<audio id=\"audio\" preload=\"auto\" src=\"data:{mime};base64,"
            )?;
            {
                let mut enc = EncoderWriter::new(&mut *out, &STANDARD);
                enc.write_all(bytes)?;
                enc.finish()?;
            }
            out.write_all(b"\"></audio>")?;
        }
        PlayerSound::Linked { src } => {
            write!(
                out,
                "<audio id=\"audio\" preload=\"auto\" src=\"{}\"></audio>",
                attribute(src)
            )?;
        }
        PlayerSound::Notes(notes) => {
            let mut json = String::with_capacity(notes.len() * 24 + 2);
            json.push('[');
            for (k, n) in notes
                .iter()
                .filter(|n| {
                    n.onset_s.is_finite()
                        && n.offset_s > n.onset_s
                        && n.midi.is_finite()
                        && n.velocity.is_finite()
                })
                .enumerate()
            {
                if k > 0 {
                    json.push(',');
                }
                let _ = write!(
                    json,
                    "[{:.3},{:.3},{:.2},{:.2}]",
                    n.onset_s,
                    n.offset_s,
                    n.midi,
                    n.velocity.clamp(0.0, 1.0)
                );
            }
            json.push(']');
            write!(
                out,
                "<script type=\"application/json\" id=\"notes\">{json}</script>"
            )?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mime_and_links_are_checked_and_escaped() {
        assert!(check_mime("audio/wav").is_ok());
        assert!(check_mime("audio/x-flac").is_ok());
        assert!(check_mime("audio\"/wav").is_err());
        assert!(check_mime("wav").is_err());
        let mut out = Vec::new();
        write_sound(&PlayerSound::Linked { src: "a \"b\".wav" }, &mut out).unwrap();
        let page = String::from_utf8(out).unwrap();
        assert!(page.contains("src=\"a &quot;b&quot;.wav\""), "{page}");
        assert!(validate(&PlayerSound::Linked { src: "" }).is_err());
    }

    #[test]
    fn notes_become_a_json_list_without_broken_ones() {
        let notes = [
            PlayerNote {
                onset_s: 0.5,
                offset_s: 1.0,
                midi: 69.0,
                velocity: 0.8,
            },
            PlayerNote {
                onset_s: 1.0,
                offset_s: 0.9,
                midi: 70.0,
                velocity: 0.8,
            },
            PlayerNote {
                onset_s: f64::NAN,
                offset_s: 2.0,
                midi: 70.0,
                velocity: 0.8,
            },
        ];
        let mut out = Vec::new();
        write_sound(&PlayerSound::Notes(&notes), &mut out).unwrap();
        let page = String::from_utf8(out).unwrap();
        assert!(
            page.ends_with("id=\"notes\">[[0.500,1.000,69.00,0.80]]</script>"),
            "{page}"
        );
    }
}
