//! MP4 video (H.264, with the audio as AAC when given) through the `ffmpeg` program: the
//! pictures are drawn here with [`FramePainter`] and piped to ffmpeg as raw RGBA; ffmpeg
//! writes a temporary file beside the target, which is renamed into place when it succeeds.
//!
//! ffmpeg is looked up on `PATH` (or taken from the `FFMPEG` environment variable); call
//! [`check_ffmpeg`] before long work so a missing program is reported first.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use skeleton::Motion;

use crate::config::RenderConfig;
use crate::draw::FramePainter;
use crate::error::{RenderError, Result};

/// The ffmpeg program: `$FFMPEG`, else `ffmpeg` on `PATH`.
fn ffmpeg_program() -> PathBuf {
    std::env::var_os("FFMPEG").map_or_else(|| PathBuf::from("ffmpeg"), PathBuf::from)
}

/// Checks that ffmpeg runs (`ffmpeg -version`); [`RenderError::FfmpegMissing`] otherwise.
pub fn check_ffmpeg() -> Result<()> {
    let program = ffmpeg_program();
    match Command::new(&program)
        .arg("-version")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
    {
        Ok(status) if status.success() => Ok(()),
        Ok(status) => Err(RenderError::Ffmpeg(format!(
            "{} -version exited with {status}",
            program.display()
        ))),
        Err(_) => Err(RenderError::FfmpegMissing),
    }
}

/// The ffmpeg command line: raw RGBA pictures on stdin, the optional audio, H.264 + AAC out.
fn ffmpeg_args(cfg: &RenderConfig, fps: f64, audio: Option<&Path>, out: &Path) -> Vec<String> {
    let mut args: Vec<String> = [
        "-hide_banner",
        "-loglevel",
        "error",
        "-nostdin",
        "-y",
        "-f",
        "rawvideo",
        "-pix_fmt",
        "rgba",
        "-s",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    args.push(format!("{}x{}", cfg.width, cfg.height));
    args.extend([
        "-framerate".into(),
        format!("{fps}"),
        "-i".into(),
        "-".into(),
    ]);
    if let Some(a) = audio {
        args.extend(["-i".into(), a.display().to_string()]);
    }
    args.extend(["-map", "0:v:0"].map(String::from));
    if audio.is_some() {
        args.extend(
            ["-map", "1:a:0", "-c:a", "aac", "-b:a", "160k", "-shortest"].map(String::from),
        );
    }
    args.extend(
        [
            "-c:v",
            "libx264",
            "-pix_fmt",
            "yuv420p",
            "-crf",
            "20",
            "-preset",
            "veryfast",
            "-movflags",
            "+faststart",
            "-map_metadata",
            "-1",
            "-fflags",
            "+bitexact",
            "-flags",
            "+bitexact",
            "-f",
            "mp4",
        ]
        .map(String::from),
    );
    args.push(out.display().to_string());
    args
}

/// The last non-empty line of ffmpeg's error output (its most specific message).
fn last_line(stderr: &str) -> String {
    stderr
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("no message")
        .trim()
        .to_string()
}

/// Waits for ffmpeg; an error names its exit status and last message.
fn finish(mut child: Child, stderr: std::thread::JoinHandle<String>) -> Result<()> {
    let status = child
        .wait()
        .map_err(|e| RenderError::Ffmpeg(format!("cannot wait for ffmpeg ({e})")))?;
    let text = stderr.join().unwrap_or_default();
    if status.success() {
        Ok(())
    } else {
        Err(RenderError::Ffmpeg(format!(
            "ffmpeg exited with {status}: {}",
            last_line(&text)
        )))
    }
}

/// Pipes every picture of `motion` (at [`RenderConfig::frame_indices`]) into ffmpeg.
fn encode(
    motion: &Motion,
    cfg: &RenderConfig,
    audio: Option<&Path>,
    out: &Path,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<()> {
    let mut painter = FramePainter::new(motion, cfg, true)?;
    let indices = cfg.frame_indices(motion);
    let fps = cfg.effective_fps(motion);
    let mut child = Command::new(ffmpeg_program())
        .args(ffmpeg_args(cfg, fps, audio, out))
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => RenderError::FfmpegMissing,
            _ => RenderError::Ffmpeg(format!("cannot start ffmpeg ({e})")),
        })?;
    let mut err_pipe = child.stderr.take();
    let stderr = std::thread::spawn(move || {
        let mut text = String::new();
        if let Some(p) = err_pipe.as_mut() {
            let _ = p.read_to_string(&mut text);
        }
        text
    });
    let Some(mut stdin) = child.stdin.take() else {
        return finish(child, stderr);
    };
    for (k, &f) in indices.iter().enumerate() {
        painter.draw(motion, f);
        if stdin.write_all(painter.pixmap().data()).is_err() {
            // ffmpeg stopped reading: its own message says why.
            drop(stdin);
            finish(child, stderr)?;
            return Err(RenderError::Ffmpeg(
                "ffmpeg stopped reading the pictures".into(),
            ));
        }
        progress(k + 1, indices.len());
    }
    drop(stdin);
    finish(child, stderr)
}

/// Writes `motion` as an MP4 video at `path` (H.264, yuv420p, `cfg.width`×`cfg.height` at
/// [`RenderConfig::effective_fps`]), with `audio` (any file ffmpeg reads) as AAC, cut to the
/// shorter of the two; calls `progress(done, total)` after each picture.
///
/// The video goes to a temporary file beside `path`, renamed into place when ffmpeg
/// succeeds, so a failure leaves no partial file. Width and height must be even (H.264 in
/// yuv420p); standard output and special files are refused (MP4 needs a seekable file).
pub fn write_mp4_file(
    motion: &Motion,
    path: &Path,
    cfg: &RenderConfig,
    audio: Option<&Path>,
    mut progress: impl FnMut(usize, usize),
) -> Result<()> {
    cfg.validate()?;
    if !cfg.width.is_multiple_of(2) || !cfg.height.is_multiple_of(2) {
        return Err(RenderError::InvalidConfig(format!(
            "MP4 picture size {}×{}: width and height must be even",
            cfg.width, cfg.height
        )));
    }
    if motion.is_empty() {
        return Err(RenderError::EmptyMotion);
    }
    if atomic_file::destination(path) != atomic_file::Destination::Regular {
        return Err(RenderError::Ffmpeg(format!(
            "{}: an MP4 must be written to a regular file",
            path.display()
        )));
    }
    let io = |source: std::io::Error| RenderError::Io {
        path: path.to_path_buf(),
        source,
    };
    let tmp = tempfile::Builder::new()
        .prefix(".violin-skeleton-")
        .suffix(".tmp.mp4")
        .tempfile_in(atomic_file::parent_dir(path))
        .map_err(io)?;
    encode(motion, cfg, audio, tmp.path(), &mut progress)?;
    atomic_file::make_ordinary(tmp.path(), false);
    tmp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_command_line_maps_audio_only_when_given() {
        let cfg = RenderConfig {
            width: 640,
            height: 360,
            ..Default::default()
        };
        let silent = ffmpeg_args(&cfg, 30.0, None, Path::new("o.mp4"));
        assert!(silent.windows(2).any(|w| w == ["-s", "640x360"]));
        assert!(silent.windows(2).any(|w| w == ["-framerate", "30"]));
        assert!(!silent.iter().any(|a| a == "1:a:0" || a == "-shortest"));
        let with = ffmpeg_args(
            &cfg,
            15.0,
            Some(Path::new("take 1.wav")),
            Path::new("o.mp4"),
        );
        assert!(with.windows(2).any(|w| w == ["-i", "take 1.wav"]));
        assert!(with.windows(2).any(|w| w == ["-c:a", "aac"]));
        assert!(with.iter().any(|a| a == "-shortest"));
        assert_eq!(with.last().map(String::as_str), Some("o.mp4"));
    }

    #[test]
    fn the_last_message_line_is_kept() {
        assert_eq!(last_line("a\nb: No such file\n\n"), "b: No such file");
        assert_eq!(last_line(""), "no message");
    }

    #[test]
    fn odd_sizes_are_refused_before_ffmpeg_runs() {
        let motion = Motion::new(30.0, ndarray::Array3::zeros((3, 10, 2))).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let cfg = RenderConfig {
            width: 641,
            ..Default::default()
        };
        let err = write_mp4_file(&motion, &dir.path().join("o.mp4"), &cfg, None, |_, _| {});
        assert!(matches!(err, Err(RenderError::InvalidConfig(_))));
    }
}
