//! The `--preview` of `generate` and the HTML output of `render`: which sound the player
//! gets. Audio up to [`EMBED_LIMIT_BYTES`] is embedded (one self-contained page); larger
//! audio is linked by its path relative to the page (a small page that plays while the two
//! stay together), unless `--embed-audio` asks for it in the page; MIDI input gets its notes
//! synthesized in the browser.

use std::path::{Component, Path, PathBuf};

use violin_skeleton::skeleton_render::{
    audio_mime, check_ffmpeg, write_gif_file, write_html_player_file_with, write_mp4_file,
    PlayerNote, PlayerSound, RenderConfig,
};
use violin_skeleton::{Motion, Note};

use crate::error::CliError;

/// Audio files up to this size are embedded in the HTML player by default (about 2 minutes
/// of 128 kbit/s MP3; a 3-minute 44.1 kHz WAV is 15 MiB and is linked instead).
pub const EMBED_LIMIT_BYTES: u64 = 2 << 20;

/// Where the player's sound comes from.
#[derive(Debug, Clone, Copy)]
pub enum SoundSource<'a> {
    /// No sound.
    None,
    /// An audio file; `embed` forces it into the page whatever its size.
    Audio {
        /// The file.
        path: &'a Path,
        /// `--embed-audio`.
        embed: bool,
    },
    /// The notes of a MIDI file.
    Notes(&'a [Note]),
}

/// `path` relative to folder `from` when both resolve, else `path` made absolute.
fn relative_to(path: &Path, from: &Path) -> PathBuf {
    let (Ok(target), Ok(base)) = (std::fs::canonicalize(path), std::fs::canonicalize(from)) else {
        return std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    };
    let t: Vec<Component> = target.components().collect();
    let b: Vec<Component> = base.components().collect();
    let common = t.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut rel = PathBuf::new();
    for _ in common..b.len() {
        rel.push("..");
    }
    for c in &t[common..] {
        rel.push(c.as_os_str());
    }
    rel
}

/// A link for an `<audio src>`: the path with `/` separators and URL-escaped characters.
fn url_path(path: &Path) -> String {
    let text = path.to_string_lossy().replace('\\', "/");
    let mut out = String::with_capacity(text.len());
    for b in text.bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'_' | b'.' | b'~' | b'/' => {
                out.push(b as char)
            }
            _ => out.push_str(&format!("%{b:02X}")),
        }
    }
    if path.is_absolute() {
        format!("file://{out}")
    } else {
        out
    }
}

/// Writes the HTML player at `page` with the sound of `source`; returns a note for the user
/// when the audio was linked rather than embedded.
pub fn write_player(
    motion: &Motion,
    page: &Path,
    source: SoundSource<'_>,
) -> Result<Option<String>, CliError> {
    let unreadable = |path: &Path, e: std::io::Error| CliError::Output {
        path: path.to_path_buf(),
        reason: format!("cannot read the audio for the player ({e})"),
    };
    let mut note = None;
    match source {
        SoundSource::None => write_html_player_file_with(motion, &PlayerSound::None, page)?,
        SoundSource::Notes(notes) => {
            let notes: Vec<PlayerNote> = notes
                .iter()
                .map(|n| PlayerNote {
                    onset_s: n.onset_s,
                    offset_s: n.offset_s,
                    midi: f32::from(n.midi),
                    velocity: n.velocity.map_or(0.7, |v| f32::from(v) / 127.0),
                })
                .collect();
            write_html_player_file_with(motion, &PlayerSound::Notes(&notes), page)?;
        }
        SoundSource::Audio { path, embed } => {
            let mime = audio_mime(path).unwrap_or("audio/wav");
            let size = std::fs::metadata(path)
                .map_err(|e| unreadable(path, e))?
                .len();
            if embed || size <= EMBED_LIMIT_BYTES {
                let bytes = std::fs::read(path).map_err(|e| unreadable(path, e))?;
                let sound = PlayerSound::Embedded {
                    bytes: &bytes,
                    mime,
                };
                write_html_player_file_with(motion, &sound, page)?;
            } else {
                let folder = atomic_file::parent_dir(page);
                let link = url_path(&relative_to(path, &folder));
                write_html_player_file_with(motion, &PlayerSound::Linked { src: &link }, page)?;
                note = Some(format!(
                    "{}: plays {} from beside it ({:.1} MiB, over the {} MiB embedding limit); keep them together, or add --embed-audio for one self-contained page",
                    page.display(),
                    link,
                    size as f64 / (1 << 20) as f64,
                    EMBED_LIMIT_BYTES >> 20
                ));
            }
        }
    }
    Ok(note)
}

/// The kinds of preview.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PreviewKind {
    Gif,
    Html,
    Mp4,
}

/// Picture size and rate of an MP4 preview (the motion's own rate, at most this).
pub const MP4_PREVIEW: (u32, u32, f64) = (640, 360, 30.0);

/// The kind a `--preview` name asks for: `.gif`, `.html`/`.htm` or `.mp4`, else a usage
/// error.
fn preview_kind(path: &Path) -> Result<PreviewKind, CliError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("gif") => Ok(PreviewKind::Gif),
        Some("html") | Some("htm") => Ok(PreviewKind::Html),
        Some("mp4") => Ok(PreviewKind::Mp4),
        _ => Err(CliError::Usage(format!(
            "--preview {}: use a .gif, .html or .mp4 file name",
            path.display()
        ))),
    }
}

/// Refuses a `--preview` name that is not `.gif`, `.html` or `.mp4`, and an `.mp4` when
/// ffmpeg is missing (before any work is done).
pub fn check_preview_name(path: &Path) -> Result<(), CliError> {
    if preview_kind(path)? == PreviewKind::Mp4 {
        check_ffmpeg()?;
    }
    Ok(())
}

/// Writes a `.gif`, `.html` or `.mp4` preview.
pub fn write_preview(
    motion: &Motion,
    path: &Path,
    source: SoundSource<'_>,
) -> Result<Option<String>, CliError> {
    match preview_kind(path)? {
        PreviewKind::Gif => {
            write_gif_file(motion, path, &RenderConfig::default())?;
            Ok(None)
        }
        PreviewKind::Html => write_player(motion, path, source),
        PreviewKind::Mp4 => {
            let (width, height, fps_out) = MP4_PREVIEW;
            let cfg = RenderConfig {
                width,
                height,
                fps_out,
                ..RenderConfig::default()
            };
            let audio = match source {
                SoundSource::Audio { path, .. } => Some(path),
                SoundSource::None | SoundSource::Notes(_) => None,
            };
            write_mp4_file(motion, path, &cfg, audio, |_, _| {})?;
            Ok(None)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_are_relative_to_the_page_and_escaped() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("pages")).unwrap();
        let audio = dir.path().join("my take.wav");
        std::fs::write(&audio, b"RIFF").unwrap();
        let rel = relative_to(&audio, &dir.path().join("pages"));
        assert_eq!(rel, Path::new("../my take.wav"));
        assert_eq!(url_path(&rel), "../my%20take.wav");
        assert_eq!(url_path(Path::new("/a/b c.wav")), "file:///a/b%20c.wav");
    }
}
