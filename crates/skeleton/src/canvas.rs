//! Fitting a performer into a picture: one scale and offset for the whole clip, so that
//! every point of every frame (body, hands, violin, bow) lies inside with margins.

use std::str::FromStr;

use crate::error::{Result, SkeletonError};
use crate::motion::Motion;

/// Smallest canvas side that can hold a person, pixels.
pub const MIN_CANVAS_PX: u32 = 64;
/// Largest canvas side, pixels.
pub const MAX_CANVAS_PX: u32 = 16_384;

/// Share of each side left free around the performer when a motion is fitted to a canvas
/// (what `generate` and the Python package use for OpenPose output).
pub const DEFAULT_CANVAS_MARGIN: f64 = 0.05;

/// A picture size in pixels, as `--canvas WxH` gives it.
///
/// ```
/// use skeleton::Canvas;
/// let c: Canvas = "1280x720".parse()?;
/// assert_eq!((c.width_px, c.height_px), (1280, 720));
/// assert!("0x0".parse::<Canvas>().is_err());
/// assert!("abc".parse::<Canvas>().is_err());
/// assert!("640x40".parse::<Canvas>().is_err());
/// # Ok::<(), skeleton::SkeletonError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Canvas {
    /// Width, pixels.
    pub width_px: u32,
    /// Height, pixels.
    pub height_px: u32,
}

impl Default for Canvas {
    fn default() -> Self {
        Canvas {
            width_px: 1280,
            height_px: 720,
        }
    }
}

impl Canvas {
    /// A canvas of `width_px` × `height_px`, each between [`MIN_CANVAS_PX`] and
    /// [`MAX_CANVAS_PX`].
    pub fn new(width_px: u32, height_px: u32) -> Result<Canvas> {
        let ok = |v: u32| (MIN_CANVAS_PX..=MAX_CANVAS_PX).contains(&v);
        if !(ok(width_px) && ok(height_px)) {
            return Err(SkeletonError::InvalidCanvas(format!(
                "{width_px}x{height_px} is too small or too large to draw a person; each side must be {MIN_CANVAS_PX}..={MAX_CANVAS_PX} px, e.g. 1280x720"
            )));
        }
        Ok(Canvas {
            width_px,
            height_px,
        })
    }
}

impl FromStr for Canvas {
    type Err = SkeletonError;

    fn from_str(s: &str) -> Result<Canvas> {
        let bad = || {
            SkeletonError::InvalidCanvas(format!(
                "{s:?} is not a size; write WIDTHxHEIGHT in pixels, e.g. 1280x720"
            ))
        };
        let (w, h) = s.trim().split_once(['x', 'X', '×']).ok_or_else(bad)?;
        let w: u32 = w.trim().parse().map_err(|_| bad())?;
        let h: u32 = h.trim().parse().map_err(|_| bad())?;
        Canvas::new(w, h)
    }
}

/// Bounding box `(min_x, min_y, max_x, max_y)` of every 2-D point of `motion`, when it has
/// a finite one.
pub fn bounds_px(motion: &Motion) -> Option<[f32; 4]> {
    let mut b = [
        f32::INFINITY,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NEG_INFINITY,
    ];
    for track in motion.tracks_2d() {
        for p in track.rows() {
            if p[0].is_finite() && p[1].is_finite() {
                b = [
                    b[0].min(p[0]),
                    b[1].min(p[1]),
                    b[2].max(p[0]),
                    b[3].max(p[1]),
                ];
            }
        }
    }
    (b[0] <= b[2]).then_some(b)
}

impl Motion {
    /// The motion with every 2-D point moved by one scale and offset so that all points of
    /// all frames (core, instrument, performer) fill `canvas` centred, leaving `margin`
    /// (a share of each side, clamped to [0, 0.45]) free on every side; the image size
    /// becomes the canvas. 3-D tracks are unchanged.
    ///
    /// ```
    /// use ndarray::Array3;
    /// use skeleton::{canvas::bounds_px, Canvas, Motion};
    /// let mut a = Array3::<f32>::zeros((2, 10, 2));
    /// a[[1, 3, 0]] = 5000.0; // far off to the right
    /// let m = Motion::new(30.0, a)?.fitted_to_canvas(Canvas::default(), 0.05);
    /// let [x0, y0, x1, y1] = bounds_px(&m).unwrap();
    /// assert!(x0 >= 64.0 - 1e-3 && x1 <= 1216.0 + 1e-3 && y0 >= 0.0 && y1 <= 720.0);
    /// assert_eq!(m.image_size(), Some((1280, 720)));
    /// # Ok::<(), skeleton::SkeletonError>(())
    /// ```
    pub fn fitted_to_canvas(&self, canvas: Canvas, margin: f64) -> Motion {
        let mut out = self
            .clone()
            .with_image_size(canvas.width_px, canvas.height_px);
        let Some([x0, y0, x1, y1]) = bounds_px(self) else {
            return out;
        };
        let margin = if margin.is_finite() {
            margin.clamp(0.0, 0.45)
        } else {
            0.0
        };
        let (w, h) = (f64::from(canvas.width_px), f64::from(canvas.height_px));
        let (bw, bh) = (f64::from(x1 - x0), f64::from(y1 - y0));
        let fit = |room: f64, extent: f64| {
            if extent > 1e-9 {
                room * (1.0 - 2.0 * margin) / extent
            } else {
                f64::INFINITY
            }
        };
        let mut scale = fit(w, bw).min(fit(h, bh));
        if !scale.is_finite() {
            scale = 1.0;
        }
        let (cx, cy) = (0.5 * f64::from(x0 + x1), 0.5 * f64::from(y0 + y1));
        out.map_points_2d(|x, y| {
            (
                ((f64::from(x) - cx) * scale + w / 2.0) as f32,
                ((f64::from(y) - cy) * scale + h / 2.0) as f32,
            )
        });
        out
    }
}
