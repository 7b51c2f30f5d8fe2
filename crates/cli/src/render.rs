//! `violin-skeleton render`: a motion file → animated GIF, HTML player (with the audio), MP4
//! video (with the audio; needs ffmpeg), a folder of PNG frames, or a glTF binary (`.glb`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use violin_skeleton::dsp_mel::load_audio;
use violin_skeleton::skeleton::{Motion, MotionFormat};
use violin_skeleton::skeleton_render::{
    audio_mime, check_ffmpeg, write_gif_with_progress, write_mp4_file, write_png_frames,
    RenderConfig,
};

use crate::contract::{check_outputs, named, refuse_stdout_folder};
use crate::error::CliError;
use crate::generate::{is_midi, with_input};
use crate::output::write_atomically;
use crate::preview::{write_player, SoundSource};
use crate::Reporter;

/// Arguments of `render`.
#[derive(Debug, Args)]
#[command(
    after_help = "The output's extension chooses the kind: .gif (animated GIF), .html (one self-contained page with a canvas, the motion and the audio), .mp4 (H.264 video with the audio as AAC, through ffmpeg), .glb (the 3-D motion as glTF 2.0 binary), anything else a folder of PNG frames (created if missing), or with --openpose a folder of OpenPose frames fitted to --canvas.\n\nExamples:\n  violin-skeleton render motion.json -o preview.gif\n  violin-skeleton render motion.json --audio take1.wav -o player.html\n  violin-skeleton render motion.json --audio take1.wav --width 1280 --height 720 -o take1.mp4\n  violin-skeleton render motion.json -o motion.glb\n  violin-skeleton render motion.json --width 1280 --height 720 --fps 30 -o frames/\n  violin-skeleton render motion.json --openpose --canvas 1024x1024 -o poses/"
)]
pub struct RenderArgs {
    /// Motion file (motion .json; .csv, .npy or an OpenPose folder also work).
    pub input: PathBuf,
    /// The sound: for the HTML player audio (wav, mp3, ogg, flac; up to 2 MiB embedded,
    /// larger linked beside the page) or a MIDI file (its notes synthesized in the browser);
    /// for an MP4 an audio file (encoded as AAC; a MIDI file gives a silent video).
    #[arg(long)]
    pub audio: Option<PathBuf>,
    /// Put the audio in the HTML player whatever its size (one self-contained page).
    #[arg(long)]
    pub embed_audio: bool,
    /// Output: P.gif, P.html, P.mp4, P.glb or a folder for PNG frames.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Picture width in pixels (GIF, PNG, MP4; even for MP4).
    #[arg(long, default_value_t = 480)]
    pub width: u32,
    /// Picture height in pixels (GIF, PNG, MP4; even for MP4).
    #[arg(long, default_value_t = 270)]
    pub height: u32,
    /// Pictures per second (GIF, PNG, MP4; at most the motion's rate; default 15, MP4 the
    /// motion's rate).
    #[arg(long)]
    pub fps: Option<f64>,
    /// Write the output folder as OpenPose `*_keypoints.json` frames (BODY_25 and both
    /// hands, every motion frame) fitted to `--canvas`, as `generate --format openpose` does.
    #[arg(long)]
    pub openpose: bool,
    /// OpenPose picture size WIDTHxHEIGHT (with `--openpose`).
    #[arg(long, default_value = "1280x720")]
    pub canvas: String,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Gif,
    Html,
    Mp4,
    Glb,
    PngFrames,
    OpenPose,
}

fn output_kind(path: &Path) -> Result<Kind, CliError> {
    if path.is_dir() {
        return Ok(Kind::PngFrames);
    }
    match path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
    {
        None => Ok(Kind::PngFrames),
        Some(e) if e == "gif" => Ok(Kind::Gif),
        Some(e) if e == "html" || e == "htm" => Ok(Kind::Html),
        Some(e) if e == "mp4" => Ok(Kind::Mp4),
        Some(e) if e == "glb" => Ok(Kind::Glb),
        Some(e) => Err(CliError::Usage(format!(
            "-o {}: unknown output kind .{e}; use P.gif, P.html, P.mp4, P.glb or a folder name for PNG frames",
            path.display()
        ))),
    }
}

/// Checks the player's audio: a known type that decodes; returns its length in seconds.
fn check_audio(path: &Path) -> Result<f64, CliError> {
    if audio_mime(path).is_none() {
        return Err(CliError::Usage(format!(
            "--audio {}: unknown audio type; use a .wav, .mp3, .ogg, .flac or .mid file",
            path.display()
        )));
    }
    Ok(load_audio(path)?.duration_s())
}

/// Warns when the sound and the motion differ in length by more than a second.
fn warn_on_drift(audio_s: f64, motion: &Motion, report: &Reporter) {
    if (audio_s - motion.duration_s()).abs() > 1.0 {
        report.line(&format!(
            "warning: the sound lasts {audio_s:.1} s but the motion {:.1} s; they will drift apart",
            motion.duration_s()
        ));
    }
}

/// Runs `render`.
pub fn run(args: &RenderArgs, report: &Reporter) -> Result<(), CliError> {
    let t0 = Instant::now();
    let kind = match (output_kind(&args.output)?, args.openpose) {
        (Kind::PngFrames, true) => Kind::OpenPose,
        (_, true) => {
            return Err(CliError::Usage(format!(
                "-o {}: --openpose writes a folder of frames; give a folder name",
                args.output.display()
            )))
        }
        (kind, false) => kind,
    };
    let canvas = crate::generate::parse_canvas(&args.canvas)?;
    if kind == Kind::OpenPose {
        refuse_stdout_folder(
            named("-o", &args.output),
            "OpenPose output",
            "give a folder name",
        )?;
    }
    if kind == Kind::PngFrames {
        refuse_stdout_folder(
            named("-o", &args.output),
            "PNG frames output",
            "give a folder name, or -o P.gif / P.html",
        )?;
    }
    let mut inputs = vec![named("input", &args.input)];
    if let Some(a) = &args.audio {
        inputs.push(named("--audio", a));
    }
    check_outputs(&inputs, &[named("-o", &args.output)])?;
    if args.audio.is_some() && !matches!(kind, Kind::Html | Kind::Mp4) {
        return Err(CliError::Usage(
            "--audio goes only into an HTML player or an MP4; give -o P.html or P.mp4".into(),
        ));
    }
    let cfg = RenderConfig {
        width: args.width,
        height: args.height,
        // MP4 plays every motion frame unless told otherwise (the cap is the motion's rate).
        fps_out: args
            .fps
            .unwrap_or(if kind == Kind::Mp4 { f64::MAX } else { 15.0 }),
        ..RenderConfig::default()
    };
    // A bad --width, --height or --fps is a usage error (exit 2), found before any work.
    cfg.validate()
        .map_err(|e| CliError::Usage(format!("{e}; check --width, --height and --fps")))?;
    if kind == Kind::Mp4 {
        if !cfg.width.is_multiple_of(2) || !cfg.height.is_multiple_of(2) {
            return Err(CliError::Usage(format!(
                "--width {} --height {}: an MP4 needs an even width and height",
                cfg.width, cfg.height
            )));
        }
        check_ffmpeg()?;
    }
    let format = MotionFormat::from_path(&args.input)?;
    let motion = Motion::read(&args.input, format)?;
    let pictures = cfg.frame_indices(&motion).len();
    let what = match kind {
        Kind::Gif => {
            let bar = report.progress(pictures as u64, "GIF");
            write_atomically(&args.output, |w| {
                write_gif_with_progress(&motion, w, &cfg, |done, _| bar.set_position(done as u64))
                    .map_err(|e| e.to_string())
            })?;
            bar.finish_and_clear();
            format!(
                "{pictures} pictures {}×{} at {} fps",
                cfg.width,
                cfg.height,
                cfg.effective_fps(&motion)
            )
        }
        Kind::PngFrames => {
            let bar = report.progress(pictures as u64, "PNG frames");
            let n = write_png_frames(&motion, &args.output, &cfg, |done, _| {
                bar.set_position(done as u64)
            })?;
            bar.finish_and_clear();
            format!("{n} PNG frames {}×{}", cfg.width, cfg.height)
        }
        Kind::Mp4 => {
            let audio = match &args.audio {
                Some(a) if is_midi(a) => {
                    report.line(&format!(
                        "note: {} is MIDI; the MP4 has no sound (render the MIDI to audio first)",
                        a.display()
                    ));
                    None
                }
                Some(a) => {
                    warn_on_drift(check_audio(a)?, &motion, report);
                    Some(a.as_path())
                }
                None => None,
            };
            let bar = report.progress(pictures as u64, "MP4");
            write_mp4_file(&motion, &args.output, &cfg, audio, |done, _| {
                bar.set_position(done as u64)
            })?;
            bar.finish_and_clear();
            format!(
                "MP4 {pictures} pictures {}×{} at {} fps{}",
                cfg.width,
                cfg.height,
                cfg.effective_fps(&motion),
                audio.map_or(String::new(), |a| format!(" with {}", a.display()))
            )
        }
        Kind::Glb => {
            motion.write(&args.output, MotionFormat::Glb)?;
            "glTF 2.0 binary".to_string()
        }
        Kind::OpenPose => {
            let format = crate::generate::OutFormat::Openpose;
            crate::generate::write_motion(&motion, &args.output, format, canvas)?;
            format!(
                "{} OpenPose frames on a {}×{} canvas",
                motion.len(),
                canvas.width_px,
                canvas.height_px
            )
        }
        Kind::Html => {
            let midi_notes = match &args.audio {
                Some(a) if is_midi(a) => Some(
                    violin_skeleton::Pipeline::default()
                        .performance_from_midi(a)
                        .map_err(|e| with_input(e, a))?
                        .notes()
                        .to_vec(),
                ),
                _ => None,
            };
            let audio_s = match (&args.audio, &midi_notes) {
                (Some(a), None) => Some(check_audio(a)?),
                (_, Some(notes)) => notes.iter().map(|n| n.offset_s).reduce(f64::max),
                _ => None,
            };
            if let Some(audio_s) = audio_s {
                warn_on_drift(audio_s, &motion, report);
            }
            let source = match (&args.audio, &midi_notes) {
                (_, Some(notes)) => SoundSource::Notes(notes),
                (Some(a), None) => SoundSource::Audio {
                    path: a,
                    embed: args.embed_audio,
                },
                (None, None) => SoundSource::None,
            };
            if let Some(note) = write_player(&motion, &args.output, source)? {
                report.line(&note);
            }
            match &args.audio {
                Some(a) => format!("HTML player with {}", a.display()),
                None => "HTML player (no audio)".to_string(),
            }
        }
    };
    let size_kib = std::fs::metadata(&args.output)
        .ok()
        .filter(|m| m.is_file())
        .map(|m| format!(", {} KiB", m.len() / 1024))
        .unwrap_or_default();
    report.line(&format!(
        "{}: {} frames at {} fps → {} ({what}{size_kib}) in {:.0} ms",
        args.input.display(),
        motion.len(),
        motion.fps(),
        args.output.display(),
        t0.elapsed().as_secs_f64() * 1e3
    ));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_kind_follows_the_extension() {
        assert_eq!(output_kind(Path::new("a.GIF")).unwrap(), Kind::Gif);
        assert_eq!(output_kind(Path::new("a.htm")).unwrap(), Kind::Html);
        assert_eq!(output_kind(Path::new("frames")).unwrap(), Kind::PngFrames);
        assert_eq!(output_kind(Path::new("a.MP4")).unwrap(), Kind::Mp4);
        assert_eq!(output_kind(Path::new("a.glb")).unwrap(), Kind::Glb);
        assert!(output_kind(Path::new("a.mkv")).is_err());
    }
}
