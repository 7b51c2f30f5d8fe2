//! PNG pictures: one frame in memory, or a folder of numbered frames.

use std::path::Path;

use skeleton::Motion;

use crate::config::RenderConfig;
use crate::draw::FramePainter;
use crate::error::{RenderError, Result};
use crate::files::write_file_atomically;

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

/// Writes the pictures of [`RenderConfig::frame_indices`] into folder `dir` (created if
/// missing) as `frame_000000.png`, … and returns how many; `progress(done, total)` is called
/// after each. Each file is written atomically.
pub fn write_png_frames(
    motion: &Motion,
    dir: impl AsRef<Path>,
    cfg: &RenderConfig,
    mut progress: impl FnMut(usize, usize),
) -> Result<usize> {
    let dir = dir.as_ref();
    let mut painter = FramePainter::new(motion, cfg, true)?;
    std::fs::create_dir_all(dir).map_err(|source| RenderError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let indices = cfg.frame_indices(motion);
    for (k, &f) in indices.iter().enumerate() {
        painter.draw(motion, f);
        let png = painter
            .pixmap()
            .encode_png()
            .map_err(|e| RenderError::Png(e.to_string()))?;
        write_file_atomically(&dir.join(png_frame_name(k)), |w| {
            w.write_all(&png)?;
            Ok(())
        })?;
        progress(k + 1, indices.len());
    }
    Ok(indices.len())
}
