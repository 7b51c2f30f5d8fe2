//! PNG pictures: one frame in memory, or a folder of numbered frames.

use std::path::Path;

use skeleton::Motion;

use crate::config::RenderConfig;
use crate::draw::FramePainter;
use crate::error::{RenderError, Result};

/// File name of picture `k` in a frames folder: `frame_000000.png`, …
pub fn png_frame_name(k: usize) -> String {
    format!("frame_{k:06}.png")
}

/// One motion frame as PNG bytes (anti-aliased).
///
/// ```
/// use ndarray::Array3;
/// let motion = skeleton::Motion::new(30.0, Array3::from_shape_fn((3, 10, 2), |(t, j, c)| (t + j * 9 + c) as f32))?;
/// let png = skeleton_render::render_png(&motion, 1, &skeleton_render::RenderConfig::default())?;
/// assert_eq!(&png[1..4], b"PNG");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn render_png(motion: &Motion, frame: usize, cfg: &RenderConfig) -> Result<Vec<u8>> {
    let mut painter = FramePainter::new(motion, cfg, true)?;
    painter.draw(motion, frame);
    painter
        .pixmap()
        .encode_png()
        .map_err(|e| RenderError::Png(e.to_string()))
}

/// `true` for the names [`write_png_frames`] writes (`frame_NNNNNN.png`).
fn is_frame_name(name: &str) -> bool {
    name.strip_prefix("frame_")
        .and_then(|rest| rest.strip_suffix(".png"))
        .is_some_and(|digits| !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()))
}

/// Writes the pictures of [`RenderConfig::frame_indices`] into folder `dir` as
/// `frame_000000.png`, … and returns how many; `progress(done, total)` is called after each.
///
/// The folder is written atomically ([`atomic_file::replace_dir_atomically`]): filled under a
/// temporary name and renamed into place, so a reused folder holds exactly this run's frames
/// (none left over from a longer earlier run). An existing folder is replaced only when it
/// holds nothing but `frame_*.png` files; otherwise it is an error and nothing is touched.
pub fn write_png_frames(
    motion: &Motion,
    dir: impl AsRef<Path>,
    cfg: &RenderConfig,
    mut progress: impl FnMut(usize, usize),
) -> Result<usize> {
    let dir = dir.as_ref();
    let mut painter = FramePainter::new(motion, cfg, true)?;
    let indices = cfg.frame_indices(motion);
    let fill = |tmp: &Path| -> Result<()> {
        for (k, &f) in indices.iter().enumerate() {
            painter.draw(motion, f);
            let png = painter
                .pixmap()
                .encode_png()
                .map_err(|e| RenderError::Png(e.to_string()))?;
            let file = tmp.join(png_frame_name(k));
            std::fs::write(&file, &png).map_err(|source| RenderError::Io {
                path: dir.join(png_frame_name(k)),
                source,
            })?;
            progress(k + 1, indices.len());
        }
        Ok(())
    };
    atomic_file::replace_dir_atomically(dir, &is_frame_name, fill).map_err(|e| match e {
        atomic_file::AtomicWriteError::Io(source) => RenderError::Io {
            path: dir.to_path_buf(),
            source,
        },
        atomic_file::AtomicWriteError::Write(e) => e,
    })?;
    Ok(indices.len())
}
