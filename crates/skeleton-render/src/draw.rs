//! Drawing one frame: bones, joints, the violin and the bow, with tiny-skia.

use skeleton::{InstrumentPoint, Joint, Motion, BONES};
use tiny_skia::{Color, FillRule, LineCap, Paint, PathBuilder, Pixmap, Stroke, Transform};

use crate::config::{Layout, RenderConfig, Rgb};
use crate::error::{RenderError, Result};

/// The drawing colours, in palette order after the background (GIF palette indices 1..).
pub const INK: [Rgb; 9] = [
    Rgb(190, 190, 200), // 1 trunk (neck, hips)
    Rgb(255, 150, 60),  // 2 right (bowing) arm
    Rgb(90, 175, 255),  // 3 left arm
    Rgb(245, 215, 120), // 4 head
    Rgb(250, 250, 250), // 5 joints
    Rgb(176, 96, 38),   // 6 violin body
    Rgb(105, 55, 22),   // 7 violin neck, scroll and outline
    Rgb(225, 210, 170), // 8 bow stick
    Rgb(40, 40, 46),    // 9 bow frog
];

const TRUNK: usize = 0;
const RIGHT: usize = 1;
const LEFT: usize = 2;
const HEAD: usize = 3;
const JOINT: usize = 4;
const VIOLIN: usize = 5;
const VIOLIN_DARK: usize = 6;
const BOW: usize = 7;
const FROG: usize = 8;

/// Violin outline: (position along the axis, half width), both in units of the distance
/// from the body centre (the bridge) to the scroll; from the lower bout to the upper one.
const OUTLINE: [(f32, f32); 11] = [
    (-0.38, 0.0),
    (-0.36, 0.09),
    (-0.30, 0.155),
    (-0.20, 0.17),
    (-0.09, 0.14),
    (0.02, 0.095),
    (0.12, 0.105),
    (0.25, 0.14),
    (0.36, 0.125),
    (0.43, 0.07),
    (0.455, 0.0),
];

/// Apparent width of the violin relative to its true outline (seen obliquely).
const VIOLIN_APPARENT_WIDTH: f32 = 0.75;

fn colour(c: Rgb) -> Color {
    Color::from_rgba8(c.0, c.1, c.2, 255)
}

/// Draws frames of one motion into a reusable picture.
pub struct FramePainter {
    layout: Layout,
    pixmap: Pixmap,
    paints: Vec<Paint<'static>>,
    background: Color,
    line_px: f32,
}

impl FramePainter {
    /// A painter for `motion` under `cfg`. `anti_alias` off draws only the exact palette
    /// colours (what the GIF encoder wants); on gives smoother PNGs.
    pub fn new(motion: &Motion, cfg: &RenderConfig, anti_alias: bool) -> Result<FramePainter> {
        cfg.validate()?;
        if motion.is_empty() {
            return Err(RenderError::EmptyMotion);
        }
        let layout = Layout::fit(motion, cfg)?;
        let pixmap = Pixmap::new(cfg.width, cfg.height)
            .ok_or_else(|| RenderError::InvalidConfig("cannot allocate the picture".into()))?;
        let paints = INK
            .iter()
            .map(|&c| {
                let mut p = Paint::default();
                p.set_color(colour(c));
                p.anti_alias = anti_alias;
                p
            })
            .collect();
        Ok(FramePainter {
            layout,
            pixmap,
            paints,
            background: colour(cfg.background),
            line_px: (cfg.height.min(cfg.width) as f32 / 110.0).max(1.0),
        })
    }

    /// The picture drawn last.
    pub fn pixmap(&self) -> &Pixmap {
        &self.pixmap
    }

    fn line(&mut self, ink: usize, a: (f32, f32), b: (f32, f32), width: f32) {
        let mut pb = PathBuilder::new();
        pb.move_to(a.0, a.1);
        pb.line_to(b.0, b.1);
        if let Some(path) = pb.finish() {
            let stroke = Stroke {
                width,
                line_cap: LineCap::Round,
                ..Stroke::default()
            };
            self.pixmap.stroke_path(
                &path,
                &self.paints[ink],
                &stroke,
                Transform::identity(),
                None,
            );
        }
    }

    fn dot(&mut self, ink: usize, c: (f32, f32), r: f32) {
        if let Some(path) = PathBuilder::from_circle(c.0, c.1, r.max(0.5)) {
            self.pixmap.fill_path(
                &path,
                &self.paints[ink],
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
    }

    fn ring(&mut self, ink: usize, c: (f32, f32), r: f32, width: f32) {
        if let Some(path) = PathBuilder::from_circle(c.0, c.1, r.max(0.5)) {
            let stroke = Stroke {
                width,
                ..Stroke::default()
            };
            self.pixmap.stroke_path(
                &path,
                &self.paints[ink],
                &stroke,
                Transform::identity(),
                None,
            );
        }
    }

    fn violin(&mut self, body: (f32, f32), scroll: (f32, f32)) {
        let (dx, dy) = (scroll.0 - body.0, scroll.1 - body.1);
        let len = (dx * dx + dy * dy).sqrt();
        if !(len.is_finite() && len > 0.5) {
            return;
        }
        let (ax, ay) = (dx, dy); // along, scaled by the bridge → scroll length
        let (px, py) = (-dy * VIOLIN_APPARENT_WIDTH, dx * VIOLIN_APPARENT_WIDTH);
        let at = |t: f32, w: f32| (body.0 + ax * t + px * w, body.1 + ay * t + py * w);
        let mut pb = PathBuilder::new();
        let (x0, y0) = at(OUTLINE[0].0, 0.0);
        pb.move_to(x0, y0);
        for &(t, w) in OUTLINE.iter().skip(1) {
            let (x, y) = at(t, w);
            pb.line_to(x, y);
        }
        for &(t, w) in OUTLINE.iter().rev().skip(1) {
            let (x, y) = at(t, -w);
            pb.line_to(x, y);
        }
        pb.close();
        if let Some(path) = pb.finish() {
            self.pixmap.fill_path(
                &path,
                &self.paints[VIOLIN],
                FillRule::Winding,
                Transform::identity(),
                None,
            );
            let stroke = Stroke {
                width: (self.line_px * 0.5).max(1.0),
                ..Stroke::default()
            };
            self.pixmap.stroke_path(
                &path,
                &self.paints[VIOLIN_DARK],
                &stroke,
                Transform::identity(),
                None,
            );
        }
        // Fingerboard/neck from the upper bout to the scroll, then the scroll.
        let neck_start = at(0.2, 0.0);
        self.line(VIOLIN_DARK, neck_start, scroll, self.line_px * 0.9);
        self.dot(VIOLIN_DARK, scroll, self.line_px * 1.1);
    }

    /// Draws motion frame `frame` (clamped to the last frame).
    pub fn draw(&mut self, motion: &Motion, frame: usize) {
        self.pixmap.fill(self.background);
        if motion.is_empty() {
            return;
        }
        let f = frame.min(motion.len() - 1);
        let joints = motion.frames();
        let finite = |x: f32, y: f32| x.is_finite() && y.is_finite();
        let layout = self.layout;
        let at = |j: Joint| {
            let (x, y) = (joints[[f, j.index(), 0]], joints[[f, j.index(), 1]]);
            finite(x, y).then(|| layout.map(x, y))
        };
        let inst = motion.instrument().map(|t| {
            let p = |i: InstrumentPoint| {
                let k = InstrumentPoint::ALL
                    .iter()
                    .position(|&q| q == i)
                    .unwrap_or(0);
                let (x, y) = (t[[f, k, 0]], t[[f, k, 1]]);
                finite(x, y).then(|| layout.map(x, y))
            };
            (
                p(InstrumentPoint::ViolinBody),
                p(InstrumentPoint::ViolinScroll),
                p(InstrumentPoint::BowFrog),
                p(InstrumentPoint::BowTip),
            )
        });
        let lw = self.line_px;
        // Violin under the arms, bow on top of the violin.
        if let Some((Some(body), Some(scroll), _, _)) = inst {
            self.violin(body, scroll);
        }
        if let (Some(nose), Some(neck)) = (at(Joint::Nose), at(Joint::Neck)) {
            let r = ((nose.0 - neck.0).powi(2) + (nose.1 - neck.1).powi(2)).sqrt()
                * crate::config::HEAD_RADIUS_PER_NECK;
            self.ring(HEAD, nose, r, lw * 0.8);
        }
        for (a, b) in BONES {
            let ink = match (a, b) {
                (_, Joint::Nose) => HEAD,
                (_, Joint::RShoulder | Joint::RElbow | Joint::RWrist) => RIGHT,
                (_, Joint::LShoulder | Joint::LElbow | Joint::LWrist) => LEFT,
                _ => TRUNK,
            };
            if let (Some(p), Some(q)) = (at(a), at(b)) {
                self.line(ink, p, q, lw * 1.4);
            }
        }
        if motion.performer().is_some() {
            use crate::performer_lines::{performer_point, performer_segments, Ink};
            for (a, b, ink, width) in performer_segments() {
                let ink = match ink {
                    Ink::Trunk => TRUNK,
                    Ink::Right => RIGHT,
                    Ink::Left => LEFT,
                    Ink::Head => HEAD,
                    Ink::ViolinDark => VIOLIN_DARK,
                    Ink::Bow => BOW,
                };
                let map = |k| performer_point(motion, f, k).map(|(x, y)| layout.map(x, y));
                if let (Some(p), Some(q)) = (map(a), map(b)) {
                    self.line(ink, p, q, (lw * width).max(1.0));
                }
            }
        }
        if let Some((_, _, Some(frog), Some(tip))) = inst {
            self.line(BOW, frog, tip, (lw * 0.7).max(1.0));
            self.dot(FROG, frog, lw * 1.0);
        }
        for j in Joint::ALL {
            if let Some(p) = at(j) {
                self.dot(JOINT, p, lw * 1.1);
            }
        }
    }
}
