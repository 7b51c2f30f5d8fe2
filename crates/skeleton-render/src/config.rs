//! Render settings and the mapping from motion pixels to picture pixels.

use skeleton::Motion;

use crate::error::{RenderError, Result};

/// An opaque colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rgb(pub u8, pub u8, pub u8);

/// How pictures are made.
///
/// ```
/// let cfg = skeleton_render::RenderConfig { width: 320, height: 180, ..Default::default() };
/// assert_eq!(cfg.fps_out, 15.0);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct RenderConfig {
    /// Picture width, pixels.
    pub width: u32,
    /// Picture height, pixels.
    pub height: u32,
    /// Pictures per second of motion for GIF and PNG frames (at most the motion's rate;
    /// frames are picked from the motion, not blended). Default 15.
    pub fps_out: f64,
    /// Zoom on top of the automatic fit (1 = fit).
    pub scale: f32,
    /// Background colour.
    pub background: Rgb,
}

impl Default for RenderConfig {
    fn default() -> Self {
        RenderConfig {
            width: 480,
            height: 270,
            fps_out: 15.0,
            scale: 1.0,
            background: Rgb(24, 26, 32),
        }
    }
}

impl RenderConfig {
    /// Checks the sizes, rate and zoom.
    pub fn validate(&self) -> Result<()> {
        if self.width == 0 || self.height == 0 || self.width > 8192 || self.height > 8192 {
            return Err(RenderError::InvalidConfig(format!(
                "picture size {}×{}: width and height must be 1..=8192",
                self.width, self.height
            )));
        }
        if !(self.fps_out.is_finite() && self.fps_out > 0.0) {
            return Err(RenderError::InvalidConfig(format!(
                "fps_out {} must be a positive number",
                self.fps_out
            )));
        }
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return Err(RenderError::InvalidConfig(format!(
                "scale {} must be a positive number",
                self.scale
            )));
        }
        Ok(())
    }

    /// The motion frames shown, one per picture: picture `k` shows the motion at time
    /// `k / fps_out` (nearest earlier frame); never more pictures than motion frames.
    pub fn frame_indices(&self, motion: &Motion) -> Vec<usize> {
        let n = motion.len();
        let rate = self.fps_out.min(motion.fps());
        let count = ((n as f64 * rate / motion.fps()) - 1e-9).ceil().max(0.0) as usize;
        (0..count)
            .map(|k| {
                ((k as f64 * motion.fps() / rate + 1e-9).floor() as usize).min(n.saturating_sub(1))
            })
            .collect()
    }

    /// The pictures' rate after capping at the motion's.
    pub fn effective_fps(&self, motion: &Motion) -> f64 {
        self.fps_out.min(motion.fps())
    }
}

/// Maps motion pixels to picture pixels: `out = (p − centre) · scale + picture centre`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layout {
    /// Motion-space point put at the picture's centre.
    pub centre: [f32; 2],
    /// Picture pixels per motion pixel.
    pub scale: f32,
    /// Picture centre.
    pub out_centre: [f32; 2],
}

/// The drawn head's radius as a fraction of the nose–neck distance.
pub(crate) const HEAD_RADIUS_PER_NECK: f32 = 0.42;

impl Layout {
    /// Fits `motion` into the picture: the motion's image (when its size is known and it
    /// has no whole-performer track) fills the picture, else the bounding box of every finite point over all frames fills 90 %
    /// of it; then [`RenderConfig::scale`] zooms.
    pub fn fit(motion: &Motion, cfg: &RenderConfig) -> Result<Layout> {
        let (w, h) = (cfg.width as f32, cfg.height as f32);
        let out_centre = [w / 2.0, h / 2.0];
        let whole_performer = motion.performer().is_some();
        if let Some((iw, ih)) = motion
            .image_size()
            .filter(|&(a, b)| a > 0 && b > 0 && !whole_performer)
        {
            let (iw, ih) = (iw as f32, ih as f32);
            return Ok(Layout {
                centre: [iw / 2.0, ih / 2.0],
                scale: (w / iw).min(h / ih) * cfg.scale,
                out_centre,
            });
        }
        let mut lo = [f32::INFINITY; 2];
        let mut hi = [f32::NEG_INFINITY; 2];
        for track in motion.tracks_2d() {
            for p in track.rows() {
                if p[0].is_finite() && p[1].is_finite() {
                    for c in 0..2 {
                        lo[c] = lo[c].min(p[c]);
                        hi[c] = hi[c].max(p[c]);
                    }
                }
            }
        }
        // The head is drawn as a circle around the nose (radius 0.42 × nose–neck, see
        // `draw`): it belongs in the box too, or the top of the head is cut off.
        let (nose, neck) = (skeleton::Joint::Nose.index(), skeleton::Joint::Neck.index());
        for frame in motion.frames().outer_iter() {
            let (n, k) = (frame.row(nose), frame.row(neck));
            let r = HEAD_RADIUS_PER_NECK * (n[0] - k[0]).hypot(n[1] - k[1]);
            if r.is_finite() && n[0].is_finite() && n[1].is_finite() {
                for c in 0..2 {
                    lo[c] = lo[c].min(n[c] - r);
                    hi[c] = hi[c].max(n[c] + r);
                }
            }
        }
        if !(lo[0].is_finite() && hi[0].is_finite()) {
            return Err(RenderError::NothingToFrame);
        }
        let (bw, bh) = ((hi[0] - lo[0]).max(1e-3), (hi[1] - lo[1]).max(1e-3));
        Ok(Layout {
            centre: [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0],
            scale: 0.9 * (w / bw).min(h / bh) * cfg.scale,
            out_centre,
        })
    }

    /// Picture coordinates of a motion point.
    pub fn map(&self, x: f32, y: f32) -> (f32, f32) {
        (
            (x - self.centre[0]) * self.scale + self.out_centre[0],
            (y - self.centre[1]) * self.scale + self.out_centre[1],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::Array3;

    #[test]
    fn frame_indices_subsample_and_cover_the_motion() {
        let m = Motion::new(30.0, Array3::zeros((300, 10, 2))).unwrap();
        let cfg = RenderConfig::default();
        let idx = cfg.frame_indices(&m);
        assert_eq!(idx.len(), 150);
        assert_eq!(&idx[..3], &[0, 2, 4]);
        let all = RenderConfig {
            fps_out: 60.0,
            ..cfg.clone()
        }
        .frame_indices(&m);
        assert_eq!(all.len(), 300);
        let odd = RenderConfig {
            fps_out: 12.0,
            ..cfg
        }
        .frame_indices(&m);
        assert_eq!(odd.len(), 120);
        assert_eq!(&odd[..3], &[0, 2, 5]);
    }

    #[test]
    fn the_drawn_head_fits_in_the_picture() {
        // A motion without an image size (CSV, NPY): nose at the top of the points, the neck
        // 40 px below it, so the head circle reaches 16.8 px above the nose.
        let mut a = Array3::<f32>::zeros((1, 10, 2));
        for j in 0..10 {
            a[[0, j, 0]] = 100.0 + 10.0 * j as f32;
            a[[0, j, 1]] = 200.0 + 20.0 * j as f32;
        }
        a[[0, skeleton::Joint::Nose.index(), 1]] = 100.0;
        a[[0, skeleton::Joint::Neck.index(), 1]] = 140.0;
        a[[0, skeleton::Joint::Nose.index(), 0]] = 150.0;
        a[[0, skeleton::Joint::Neck.index(), 0]] = 150.0;
        let m = Motion::new(30.0, a).unwrap();
        let cfg = RenderConfig::default();
        let l = Layout::fit(&m, &cfg).unwrap();
        let (_, top) = l.map(150.0, 100.0 - 0.42 * 40.0);
        assert!(top >= 0.0, "the head's top is drawn at y = {top}");
    }

    #[test]
    fn layout_fits_the_image_or_the_points() {
        let mut a = Array3::<f32>::zeros((2, 10, 2));
        a[[0, 0, 0]] = -50.0;
        a[[1, 3, 1]] = 100.0;
        let m = Motion::new(30.0, a).unwrap();
        let cfg = RenderConfig {
            width: 200,
            height: 100,
            ..Default::default()
        };
        let l = Layout::fit(&m, &cfg).unwrap();
        let (x, y) = l.map(-50.0, 100.0);
        assert!(x >= 0.0 && y <= 100.0 && y > 90.0);
        let m = m.with_image_size(400, 200);
        let l = Layout::fit(&m, &cfg).unwrap();
        assert_eq!(l.map(0.0, 0.0), (0.0, 0.0));
        assert_eq!(l.map(400.0, 200.0), (200.0, 100.0));
        assert!(RenderConfig { width: 0, ..cfg }.validate().is_err());
    }
}
