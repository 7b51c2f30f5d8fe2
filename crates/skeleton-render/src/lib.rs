//! # skeleton-render
//!
//! Preview pictures of a violinist skeleton ([`skeleton::Motion`]): bones, joints, the
//! violin (body outline, neck and scroll) and the bow (frog → tip line) when the motion
//! carries instrument points.
//!
//! * [`write_gif`] / [`write_gif_file`]: an animated GIF (fixed 16-colour palette, only the
//!   changed rectangle of each picture stored; may subsample to [`RenderConfig::fps_out`]).
//! * [`render_png`] / [`write_png_frames`]: anti-aliased PNG pictures.
//! * [`write_html_player`] / [`write_html_player_file`]: one self-contained HTML file with
//!   the motion as JSON and the audio as a base64 data URI, drawn in sync with the audio
//!   (`?t=SECONDS` and `window.seek(t)` for scripted checks).
//! * [`write_mp4_file`]: an H.264 MP4 with the audio (AAC) through the `ffmpeg` program
//!   ([`check_ffmpeg`] says early whether it is installed).
//!
//! Motion pixels are fitted to the picture by [`Layout::fit`]: the motion's image (when
//! its size is known) fills the picture, otherwise the bounding box of all its points.
//!
//! ```
//! use ndarray::Array3;
//! use skeleton_render::{write_gif, write_html_player, RenderConfig};
//! let motion = skeleton::Motion::new(30.0, Array3::from_shape_fn((60, 10, 2), |(t, j, c)| {
//!     (j * 30 + c * 50) as f32 + (t as f32 / 5.0).sin() * 10.0
//! }))?;
//! let mut gif = Vec::new();
//! write_gif(&motion, &mut gif, &RenderConfig { width: 160, height: 90, ..Default::default() })?;
//! let mut html = Vec::new();
//! write_html_player(&motion, None, &mut html)?;
//! assert!(gif.len() > 100 && html.len() > 1000);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod config;
pub mod draw;
mod error;
mod files;
mod gif_out;
mod html;
mod mp4_out;
pub mod performer_lines;
mod player_sound;
mod png_out;

pub use config::{Layout, RenderConfig, Rgb};
pub use draw::FramePainter;
pub use error::{RenderError, Result};
pub use gif_out::{write_gif, write_gif_file, write_gif_with_progress};
pub use html::{
    audio_mime, player_json, write_html_player, write_html_player_file,
    write_html_player_file_with, write_html_player_with,
};
pub use mp4_out::{check_ffmpeg, write_mp4_file};
pub use player_sound::{PlayerNote, PlayerSound};
pub use png_out::{png_frame_name, render_png, write_png_frames};

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
