//! Animated GIF: a fixed palette (background + [`crate::draw::INK`]), no anti-aliasing, and
//! only the rectangle that changed since the previous picture is stored, which keeps
//! encoding fast and files small.

use std::borrow::Cow;
use std::io::Write;
use std::path::Path;

use gif::{DisposalMethod, Encoder, Frame, Repeat};
use skeleton::Motion;

use crate::config::RenderConfig;
use crate::draw::{FramePainter, INK};
use crate::error::{RenderError, Result};
use crate::files::write_file_atomically;

fn gif_err(e: gif::EncodingError) -> RenderError {
    match e {
        gif::EncodingError::Io(io) => RenderError::Write(io),
        other => RenderError::Gif(other.to_string()),
    }
}

/// The palette as packed RGB (`0xRRGGBB`), background first, padded to 16 entries.
fn palette(cfg: &RenderConfig) -> Vec<u32> {
    let bg = cfg.background;
    let mut p: Vec<u32> = std::iter::once(bg)
        .chain(INK)
        .map(|c| (u32::from(c.0) << 16) | (u32::from(c.1) << 8) | u32::from(c.2))
        .collect();
    p.resize(16, 0);
    p
}

/// Palette index of every pixel (RGBA, opaque). Colours not in the palette (none when
/// drawing without anti-aliasing) go to the nearest entry.
fn index_pixels(rgba: &[u8], pal: &[u32], out: &mut [u8]) {
    let mut last = (u32::MAX, 0u8);
    for (px, o) in rgba.chunks_exact(4).zip(out.iter_mut()) {
        let key = (u32::from(px[0]) << 16) | (u32::from(px[1]) << 8) | u32::from(px[2]);
        if key != last.0 {
            let idx = pal
                .iter()
                .position(|&c| c == key)
                .unwrap_or_else(|| nearest(key, pal));
            last = (key, idx as u8);
        }
        *o = last.1;
    }
}

fn nearest(key: u32, pal: &[u32]) -> usize {
    let ch = |c: u32, s: u32| ((c >> s) & 0xff) as i32;
    let dist = |c: u32| {
        (0..3)
            .map(|i| (ch(c, i * 8) - ch(key, i * 8)).pow(2))
            .sum::<i32>()
    };
    (0..pal.len()).min_by_key(|&i| dist(pal[i])).unwrap_or(0)
}

/// Bounding box `(left, top, width, height)` of the pixels that differ.
fn changed_rect(a: &[u8], b: &[u8], width: usize) -> Option<(usize, usize, usize, usize)> {
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    for (y, (ra, rb)) in a.chunks_exact(width).zip(b.chunks_exact(width)).enumerate() {
        if ra == rb {
            continue;
        }
        let first = ra.iter().zip(rb).position(|(p, q)| p != q).unwrap_or(0);
        let last = width
            - 1
            - ra.iter()
                .rev()
                .zip(rb.iter().rev())
                .position(|(p, q)| p != q)
                .unwrap_or(0);
        x0 = x0.min(first);
        x1 = x1.max(last);
        y0 = y0.min(y);
        y1 = y;
    }
    (x0 != usize::MAX).then(|| (x0, y0, x1 - x0 + 1, y1 - y0 + 1))
}

/// Writes `motion` as an endlessly looping GIF at `cfg.fps_out` (see
/// [`RenderConfig::frame_indices`]).
///
/// ```
/// use ndarray::Array3;
/// use skeleton_render::{write_gif, RenderConfig};
/// let motion = skeleton::Motion::new(30.0, Array3::from_shape_fn((30, 10, 2), |(t, j, c)| (t + j * 20 + c * 7) as f32))?;
/// let mut bytes = Vec::new();
/// write_gif(&motion, &mut bytes, &RenderConfig { width: 64, height: 48, ..Default::default() })?;
/// assert_eq!(&bytes[..6], b"GIF89a");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_gif(motion: &Motion, out: impl Write, cfg: &RenderConfig) -> Result<()> {
    write_gif_with_progress(motion, out, cfg, |_, _| {})
}

/// [`write_gif`], calling `progress(done, total)` after each picture.
pub fn write_gif_with_progress(
    motion: &Motion,
    out: impl Write,
    cfg: &RenderConfig,
    mut progress: impl FnMut(usize, usize),
) -> Result<()> {
    let mut painter = FramePainter::new(motion, cfg, false)?;
    let (w, h) = (cfg.width, cfg.height);
    let (w16, h16) = (
        u16::try_from(w)
            .map_err(|_| RenderError::InvalidConfig("GIF width must be at most 65535".into()))?,
        u16::try_from(h)
            .map_err(|_| RenderError::InvalidConfig("GIF height must be at most 65535".into()))?,
    );
    let pal = palette(cfg);
    let pal_bytes: Vec<u8> = pal
        .iter()
        .flat_map(|c| [(c >> 16) as u8, (c >> 8) as u8, *c as u8])
        .collect();
    let mut enc = Encoder::new(out, w16, h16, &pal_bytes).map_err(gif_err)?;
    enc.set_repeat(Repeat::Infinite).map_err(gif_err)?;

    let indices = cfg.frame_indices(motion);
    let fps = cfg.effective_fps(motion);
    let n = (w as usize) * (h as usize);
    let mut prev = vec![0u8; n];
    let mut cur = vec![0u8; n];
    let mut sub = Vec::with_capacity(n);
    for (k, &f) in indices.iter().enumerate() {
        painter.draw(motion, f);
        index_pixels(painter.pixmap().data(), &pal, &mut cur);
        // Delays in centiseconds, rounded cumulatively so the average rate is exact.
        let delay = ((k + 1) as f64 * 100.0 / fps).round() - (k as f64 * 100.0 / fps).round();
        let rect = if k == 0 {
            Some((0, 0, w as usize, h as usize))
        } else {
            changed_rect(&prev, &cur, w as usize)
        };
        let (x, y, rw, rh) = rect.unwrap_or((0, 0, 1, 1));
        sub.clear();
        for row in cur.chunks_exact(w as usize).skip(y).take(rh) {
            sub.extend_from_slice(&row[x..x + rw]);
        }
        let frame = Frame {
            delay: delay.clamp(1.0, 65535.0) as u16,
            dispose: DisposalMethod::Keep,
            left: x as u16,
            top: y as u16,
            width: rw as u16,
            height: rh as u16,
            buffer: Cow::Borrowed(&sub),
            ..Frame::default()
        };
        enc.write_frame(&frame).map_err(gif_err)?;
        std::mem::swap(&mut prev, &mut cur);
        progress(k + 1, indices.len());
    }
    enc.into_inner()?.flush()?;
    Ok(())
}

/// [`write_gif`] to a file, atomically (temporary file renamed into place).
pub fn write_gif_file(motion: &Motion, path: impl AsRef<Path>, cfg: &RenderConfig) -> Result<()> {
    write_file_atomically(path.as_ref(), |w| write_gif(motion, w, cfg))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn changed_rect_finds_the_difference() {
        let a = vec![0u8; 20];
        let mut b = a.clone();
        assert_eq!(changed_rect(&a, &b, 5), None);
        b[7] = 1; // (2, 1)
        b[13] = 1; // (3, 2)
        assert_eq!(changed_rect(&a, &b, 5), Some((2, 1, 2, 2)));
    }

    #[test]
    fn unknown_colours_map_to_the_nearest_entry() {
        let pal = vec![0x000000, 0xff0000, 0x00ff00];
        let mut out = [9u8; 3];
        index_pixels(
            &[0, 0, 0, 255, 250, 10, 0, 255, 0, 255, 0, 255],
            &pal,
            &mut out,
        );
        assert_eq!(out, [0, 1, 2]);
    }
}
