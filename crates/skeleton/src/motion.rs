//! `Motion`: joint positions over time at a fixed frame rate.

use ndarray::{Array3, ArrayView2, Axis};
use serde::{Deserialize, Serialize};

use crate::error::{Result, SkeletonError};
use crate::joint::JOINT_COUNT;
use crate::performer::PerformerTrack;

/// Points on the instrument carried with a motion (violin and bow as rigid objects).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InstrumentPoint {
    /// The bow's frog (held by the right hand).
    BowFrog,
    /// The bow's tip.
    BowTip,
    /// The violin's scroll (end of the neck).
    ViolinScroll,
    /// Centre of the violin's body (under the bridge).
    ViolinBody,
}

impl InstrumentPoint {
    /// All instrument points, in file order.
    pub const ALL: [InstrumentPoint; 4] = [
        InstrumentPoint::BowFrog,
        InstrumentPoint::BowTip,
        InstrumentPoint::ViolinScroll,
        InstrumentPoint::ViolinBody,
    ];

    /// The stable name used in files.
    pub fn name(self) -> &'static str {
        match self {
            InstrumentPoint::BowFrog => "bow_frog",
            InstrumentPoint::BowTip => "bow_tip",
            InstrumentPoint::ViolinScroll => "violin_scroll",
            InstrumentPoint::ViolinBody => "violin_body",
        }
    }
}

/// A skeleton animation: `frames[t, j, c]` is coordinate `c` (x, y) of joint
/// [`crate::Joint::ALL`]`[j]` at frame `t`, in image pixels (y down), at `fps` frames per second.
///
/// Optional tracks: a 3-D track `(T, 10, 3)` in metres (x right, y up, z towards the camera),
/// instrument points `(T, 4, 2)` in pixels and `(T, 4, 3)` in metres, and the image size the
/// pixels refer to.
///
/// ```
/// use ndarray::Array3;
/// use skeleton::{Joint, Motion};
/// let m = Motion::new(30.0, Array3::zeros((90, 10, 2)))?;
/// assert_eq!(m.len(), 90);
/// assert_eq!(m.duration_s(), 3.0);
/// assert_eq!(m.joint(Joint::RWrist).dim(), (90, 2));
/// # Ok::<(), skeleton::SkeletonError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    fps: f64,
    frames: Array3<f32>,
    frames_3d: Option<Array3<f32>>,
    instrument: Option<Array3<f32>>,
    instrument_3d: Option<Array3<f32>>,
    image_size: Option<(u32, u32)>,
    performer: Option<PerformerTrack>,
}

fn check_shape(a: &Array3<f32>, points: usize, dims: usize, frames: Option<usize>) -> Result<()> {
    let (t, j, c) = a.dim();
    if j != points || c != dims || frames.is_some_and(|n| n != t) {
        return Err(SkeletonError::Shape {
            expected: format!(
                "({}, {points}, {dims})",
                frames.map_or("frames".to_string(), |n| n.to_string())
            ),
            got: vec![t, j, c],
        });
    }
    Ok(())
}

impl Motion {
    /// A 2-D motion; `frames` must be `(T, 10, 2)`.
    pub fn new(fps: f64, frames: Array3<f32>) -> Result<Self> {
        if !(fps.is_finite() && fps > 0.0) {
            return Err(SkeletonError::InvalidFps(fps));
        }
        check_shape(&frames, JOINT_COUNT, 2, None)?;
        Ok(Self {
            fps,
            frames,
            frames_3d: None,
            instrument: None,
            instrument_3d: None,
            image_size: None,
            performer: None,
        })
    }

    /// Adds the 3-D track `(T, 10, 3)` in metres.
    pub fn with_3d(mut self, frames_3d: Array3<f32>) -> Result<Self> {
        check_shape(&frames_3d, JOINT_COUNT, 3, Some(self.len()))?;
        self.frames_3d = Some(frames_3d);
        Ok(self)
    }

    /// Adds the instrument points `(T, 4, 2)` in pixels (order of [`InstrumentPoint::ALL`]).
    pub fn with_instrument(mut self, points: Array3<f32>) -> Result<Self> {
        check_shape(&points, InstrumentPoint::ALL.len(), 2, Some(self.len()))?;
        self.instrument = Some(points);
        Ok(self)
    }

    /// Adds the instrument points in 3-D, `(T, 4, 3)` in metres.
    pub fn with_instrument_3d(mut self, points: Array3<f32>) -> Result<Self> {
        check_shape(&points, InstrumentPoint::ALL.len(), 3, Some(self.len()))?;
        self.instrument_3d = Some(points);
        Ok(self)
    }

    /// Records the image size (width, height) in pixels that the 2-D track refers to.
    pub fn with_image_size(mut self, width: u32, height: u32) -> Self {
        self.image_size = Some((width, height));
        self
    }

    /// Attaches the whole performer (BODY_25 body, hands, violin and bow); it must have the
    /// motion's number of frames. Its body points at the core joints should hold the same
    /// coordinates as the core track (`motion-synth` writes them so).
    pub fn with_performer(mut self, performer: PerformerTrack) -> Result<Self> {
        if performer.len() != self.len() {
            return Err(SkeletonError::Shape {
                expected: format!("a performer track of {} frames", self.len()),
                got: vec![performer.len()],
            });
        }
        self.performer = Some(performer);
        Ok(self)
    }

    /// The whole performer, when present (motions read from older files have none).
    pub fn performer(&self) -> Option<&PerformerTrack> {
        self.performer.as_ref()
    }

    /// Frames per second.
    pub fn fps(&self) -> f64 {
        self.fps
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.frames.len_of(Axis(0))
    }

    /// True when there are no frames.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Duration in seconds.
    pub fn duration_s(&self) -> f64 {
        self.len() as f64 / self.fps
    }

    /// The 2-D track `(T, 10, 2)`, pixels.
    pub fn frames(&self) -> &Array3<f32> {
        &self.frames
    }

    /// The 2-D track, mutable (its shape cannot change).
    pub fn frames_mut(&mut self) -> ndarray::ArrayViewMut3<'_, f32> {
        self.frames.view_mut()
    }

    /// The 3-D track `(T, 10, 3)`, metres, when present.
    pub fn frames_3d(&self) -> Option<&Array3<f32>> {
        self.frames_3d.as_ref()
    }

    /// Instrument points `(T, 4, 2)`, pixels, when present.
    pub fn instrument(&self) -> Option<&Array3<f32>> {
        self.instrument.as_ref()
    }

    /// Instrument points `(T, 4, 3)`, metres, when present.
    pub fn instrument_3d(&self) -> Option<&Array3<f32>> {
        self.instrument_3d.as_ref()
    }

    /// Image size (width, height) in pixels, when known.
    pub fn image_size(&self) -> Option<(u32, u32)> {
        self.image_size
    }

    /// One joint's 2-D track, `(T, 2)`.
    pub fn joint(&self, joint: crate::Joint) -> ArrayView2<'_, f32> {
        self.frames.index_axis(Axis(1), joint.index())
    }

    /// The per-video mean of all joints over all frames, `(x, y)` (SPEC §3 step 4).
    pub fn mean_xy(&self) -> (f32, f32) {
        let n = (self.len() * JOINT_COUNT).max(1) as f64;
        let mut sx = 0.0f64;
        let mut sy = 0.0f64;
        for p in self.frames.rows() {
            sx += f64::from(p[0]);
            sy += f64::from(p[1]);
        }
        ((sx / n) as f32, (sy / n) as f32)
    }

    /// Every 2-D track the motion has (core, instrument, performer parts), for reading.
    pub fn tracks_2d(&self) -> Vec<&Array3<f32>> {
        let mut out = vec![&self.frames];
        out.extend(self.instrument.as_ref());
        if let Some(p) = &self.performer {
            out.extend(crate::PerformerPart::ALL.map(|part| p.track(part)));
        }
        out
    }

    /// Applies `f` to every 2-D point of every track (core, instrument, performer).
    pub(crate) fn map_points_2d(&mut self, f: impl Fn(f32, f32) -> (f32, f32)) {
        let apply = |mut a: ndarray::ArrayViewMut3<'_, f32>| {
            for mut p in a.rows_mut() {
                let (x, y) = f(p[0], p[1]);
                p[0] = x;
                p[1] = y;
            }
        };
        apply(self.frames.view_mut());
        if let Some(i) = self.instrument.as_mut() {
            apply(i.view_mut());
        }
        if let Some(p) = self.performer.as_mut() {
            p.tracks_mut().for_each(apply);
        }
    }

    /// Subtracts [`Motion::mean_xy`] from every 2-D point (instrument and performer points too), so the
    /// motion is centred on the origin.
    pub fn center(&mut self) {
        let (mx, my) = self.mean_xy();
        self.map_points_2d(|x, y| (x - mx, y - my));
    }
}
