//! The HTML player: one file with a canvas, the motion as JSON and its sound
//! ([`PlayerSound`]: audio embedded as a base64 data URI, an audio file beside the page, or
//! MIDI notes synthesized in the browser).
//!
//! The page draws the frame at `audio.currentTime · fps` on every animation frame, and runs
//! on its own clock when there is no audio, when the audio cannot play (autoplay policy, no
//! sound device: its clock does not move) or for synthesized notes. It has play/pause (button, click on the picture, space bar)
//! and a scrub bar, opens at `?t=SECONDS` when the URL says so, and offers
//! `window.seek(seconds)` (returns the frame shown) and `window.currentFrame()` for
//! scripted checks; the canvas's `data-frame` attribute holds the frame drawn last.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use skeleton::{Joint, Motion, BONES};

use crate::config::{Layout, RenderConfig};
use crate::error::{RenderError, Result};
use crate::files::write_file_atomically;
use crate::player_sound::{validate, write_sound, PlayerSound};

const TEMPLATE: &str = include_str!("player.html");
const AUDIO_SLOT: &str = "__AUDIO_ELEMENT__";
const MOTION_SLOT: &str = "__MOTION_JSON__";

/// Canvas size of the player for a motion without an image size.
const DEFAULT_CANVAS: (u32, u32) = (960, 540);

fn push_point(out: &mut String, x: f32, y: f32, layout: &Layout) {
    if x.is_finite() && y.is_finite() {
        let (px, py) = layout.map(x, y);
        let _ = write!(out, "{:.1},{:.1}", px, py);
    } else {
        out.push_str("null,null");
    }
}

/// Every how many frames the player gets the performer's points (hands, legs, strings).
const PERFORMER_STEP: usize = 2;

/// The performer for the player, kept small (a 3-minute page stays under 3 MiB): only the
/// points the segments use, in whole canvas pixels, every [`PERFORMER_STEP`]th frame;
/// `performer_segments` index into that list of points.
fn push_performer(out: &mut String, motion: &Motion, layout: &Layout) {
    use crate::performer_lines::{performer_point, performer_segments};
    let segments = performer_segments();
    let mut used: Vec<usize> = segments.iter().flat_map(|s| [s.0, s.1]).collect();
    used.sort_unstable();
    used.dedup();
    let slot = |k: usize| used.binary_search(&k).unwrap_or(0);
    let _ = write!(out, ",\"performer_step\":{PERFORMER_STEP},\"performer\":[");
    for (n, f) in (0..motion.len()).step_by(PERFORMER_STEP).enumerate() {
        if n > 0 {
            out.push(',');
        }
        out.push('[');
        for (i, &k) in used.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            match performer_point(motion, f, k).map(|(x, y)| layout.map(x, y)) {
                Some((x, y)) => {
                    let _ = write!(out, "{},{}", x.round(), y.round());
                }
                None => out.push_str("null,null"),
            }
        }
        out.push(']');
    }
    out.push(']');
    let segs: Vec<(usize, usize, &str, f32)> = segments
        .iter()
        .map(|&(a, b, ink, w)| (slot(a), slot(b), ink.key(), w))
        .collect();
    out.push_str(",\"performer_segments\":");
    out.push_str(&serde_json::to_string(&segs).unwrap_or_else(|_| "[]".into()));
}

fn push_track(out: &mut String, track: &ndarray::Array3<f32>, layout: &Layout) {
    out.push('[');
    for (f, frame) in track.outer_iter().enumerate() {
        if f > 0 {
            out.push(',');
        }
        out.push('[');
        for (i, p) in frame.rows().into_iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            push_point(out, p[0], p[1], layout);
        }
        out.push(']');
    }
    out.push(']');
}

/// The motion as the player's JSON: canvas size, fps, joint names, bones (index pairs) and
/// per-frame flat `[x0, y0, x1, y1, …]` arrays in canvas pixels (`null` for a missing point).
pub fn player_json(motion: &Motion) -> Result<String> {
    if motion.is_empty() {
        return Err(RenderError::EmptyMotion);
    }
    let (w, h) = motion
        .image_size()
        .filter(|&(a, b)| a > 0 && b > 0)
        .unwrap_or(DEFAULT_CANVAS);
    let cfg = RenderConfig {
        width: w,
        height: h,
        ..RenderConfig::default()
    };
    let layout = Layout::fit(motion, &cfg)?;
    let names: Vec<&str> = Joint::ALL.iter().map(|j| j.name()).collect();
    let bones: Vec<[usize; 2]> = BONES.iter().map(|(a, b)| [a.index(), b.index()]).collect();
    let mut out = String::with_capacity(motion.len() * 200 + 512);
    let _ = write!(
        out,
        "{{\"fps\":{},\"width\":{w},\"height\":{h},\"joints\":{},\"bones\":{},\"frames\":",
        motion.fps(),
        serde_json::to_string(&names).unwrap_or_default(),
        serde_json::to_string(&bones).unwrap_or_default(),
    );
    push_track(&mut out, motion.frames(), &layout);
    if motion.performer().is_some() {
        push_performer(&mut out, motion, &layout);
    }
    out.push_str(",\"instrument\":");
    match motion.instrument() {
        Some(t) => push_track(&mut out, t, &layout),
        None => out.push_str("null"),
    }
    out.push('}');
    // Safe inside <script>: no "</script>" or "<!--" can appear.
    Ok(out.replace('<', "\\u003c"))
}

/// The MIME type of an audio file from its extension (`wav`, `mp3`, `ogg`, `flac`, `m4a`).
///
/// ```
/// assert_eq!(skeleton_render::audio_mime(std::path::Path::new("a/take.WAV")), Some("audio/wav"));
/// assert_eq!(skeleton_render::audio_mime(std::path::Path::new("x.txt")), None);
/// ```
pub fn audio_mime(path: &Path) -> Option<&'static str> {
    let ext = path.extension()?.to_string_lossy().to_ascii_lowercase();
    Some(match ext.as_str() {
        "wav" | "wave" => "audio/wav",
        "mp3" => "audio/mpeg",
        "ogg" | "oga" => "audio/ogg",
        "flac" => "audio/flac",
        "m4a" | "mp4" => "audio/mp4",
        _ => return None,
    })
}

/// Writes the player page for `motion`, with `audio` (the file's bytes and its MIME type,
/// e.g. `audio/wav`) embedded when given. [`write_html_player_with`] offers the other
/// sounds (a linked audio file, MIDI notes).
///
/// ```
/// use ndarray::Array3;
/// let motion = skeleton::Motion::new(30.0, Array3::from_elem((2, 10, 2), 5.0))?;
/// let mut page = Vec::new();
/// skeleton_render::write_html_player(&motion, Some((b"RIFF", "audio/wav")), &mut page)?;
/// let page = String::from_utf8(page).unwrap();
/// assert!(page.contains("data:audio/wav;base64,UklGRg=="));
/// assert!(page.contains("\"fps\":30"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_html_player(
    motion: &Motion,
    audio: Option<(&[u8], &str)>,
    out: impl Write,
) -> Result<()> {
    let sound = match audio {
        Some((bytes, mime)) => PlayerSound::Embedded { bytes, mime },
        None => PlayerSound::None,
    };
    write_html_player_with(motion, &sound, out)
}

/// Writes the player page for `motion` with `sound` ([`PlayerSound`]).
///
/// ```
/// use ndarray::Array3;
/// use skeleton_render::{PlayerNote, PlayerSound};
/// let motion = skeleton::Motion::new(30.0, Array3::from_elem((2, 10, 2), 5.0))?;
/// let notes = [PlayerNote { onset_s: 0.0, offset_s: 0.5, midi: 69.0, velocity: 0.7 }];
/// let mut page = Vec::new();
/// skeleton_render::write_html_player_with(&motion, &PlayerSound::Notes(&notes), &mut page)?;
/// assert!(String::from_utf8(page).unwrap().contains("[[0.000,0.500,69.00,0.70]]"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_html_player_with(
    motion: &Motion,
    sound: &PlayerSound<'_>,
    mut out: impl Write,
) -> Result<()> {
    let json = player_json(motion)?;
    validate(sound)?;
    let (head, rest) = TEMPLATE.split_once(AUDIO_SLOT).unwrap_or((TEMPLATE, ""));
    let (middle, tail) = rest.split_once(MOTION_SLOT).unwrap_or((rest, ""));
    out.write_all(head.as_bytes())?;
    write_sound(sound, &mut out)?;
    out.write_all(middle.as_bytes())?;
    out.write_all(json.as_bytes())?;
    out.write_all(tail.as_bytes())?;
    out.flush()?;
    Ok(())
}

/// [`write_html_player`] to a file, atomically.
pub fn write_html_player_file(
    motion: &Motion,
    audio: Option<(&[u8], &str)>,
    path: impl AsRef<Path>,
) -> Result<()> {
    write_file_atomically(path.as_ref(), |w| write_html_player(motion, audio, w))
}

/// [`write_html_player_with`] to a file, atomically.
pub fn write_html_player_file_with(
    motion: &Motion,
    sound: &PlayerSound<'_>,
    path: impl AsRef<Path>,
) -> Result<()> {
    write_file_atomically(path.as_ref(), |w| write_html_player_with(motion, sound, w))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn template_has_both_slots_once() {
        assert_eq!(TEMPLATE.matches(AUDIO_SLOT).count(), 1);
        assert_eq!(TEMPLATE.matches(MOTION_SLOT).count(), 1);
    }
}
