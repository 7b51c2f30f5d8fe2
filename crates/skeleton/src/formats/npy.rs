//! NPY: float32 `(T, 20)`, x and y of each joint in [`Joint::ALL`] order.

use std::io::{Read, Write};
use std::path::Path;

use ndarray::{Array2, Array3};
use ndarray_npy::{ReadNpyExt, WriteNpyExt};

use super::check::format_error;
use crate::error::{Result, SkeletonError};
use crate::joint::{Joint, JOINT_COUNT};
use crate::motion::Motion;

/// Writes the 2-D track of `motion` as a float32 `(T, 20)` NPY array to `writer`.
///
/// ```
/// use ndarray::Array3;
/// let m = skeleton::Motion::new(30.0, Array3::from_elem((5, 10, 2), 1.5))?;
/// let mut bytes = Vec::new();
/// skeleton::formats::write_npy(&m, &mut bytes)?;
/// assert_eq!(skeleton::formats::read_npy_from(bytes.as_slice(), 30.0)?, m);
/// # Ok::<(), skeleton::SkeletonError>(())
/// ```
pub fn write_npy(motion: &Motion, writer: impl Write) -> Result<()> {
    let path = super::check::memory_path();
    super::check::check_writable(motion, &path, false)?;
    write(motion, writer, &path)
}

pub(crate) fn write(motion: &Motion, writer: impl Write, path: &Path) -> Result<()> {
    let flat = motion
        .frames()
        .to_shape((motion.len(), 2 * JOINT_COUNT))
        .map_err(|e| format_error(path, e.to_string()))?;
    flat.write_npy(writer)
        .map_err(|e| format_error(path, format!("cannot write NPY: {e}")))
}

/// Reads a `(T, 20)` (or `(T, 10, 2)`) float32 or float64 NPY array from `reader` as a
/// motion at `fps`.
pub fn read_npy_from(reader: impl Read, fps: f64) -> Result<Motion> {
    let (bytes, path) = super::check::read_all(reader)?;
    read(&bytes, fps, &path)
}

/// Longest header read; numpy itself refuses longer ones by default (`max_header_size`).
const MAX_HEADER_BYTES: usize = 10_000;
/// Deepest bracket nesting read in a header. A plain array's header nests 2 (the dict's `{`
/// and the shape's `(`); the header parser `ndarray-npy` uses slows down steeply with the
/// depth (a damaged header nesting 18 `[` took over a second), so deeper ones are refused
/// before it runs.
const MAX_HEADER_NESTING: usize = 4;

/// Refuses NPY headers that are too long or nest brackets too deeply to be an array numpy
/// wrote; anything else (bad magic, short files) is left to `ndarray-npy`'s own errors.
fn check_header(bytes: &[u8], path: &Path) -> Result<()> {
    let (Some(magic), Some(&major)) = (bytes.get(..6), bytes.get(6)) else {
        return Ok(());
    };
    if magic != b"\x93NUMPY" {
        return Ok(());
    }
    let (len, start) = match (major, bytes.get(8..10), bytes.get(8..12)) {
        (1, Some(b), _) => (usize::from(u16::from_le_bytes([b[0], b[1]])), 10),
        (_, _, Some(b)) => (u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize, 12),
        _ => return Ok(()),
    };
    if len > MAX_HEADER_BYTES {
        return Err(format_error(
            path,
            format!("its NPY header is {len} bytes, numpy writes at most {MAX_HEADER_BYTES}: the file is damaged, write it again with numpy.save"),
        ));
    }
    let header = bytes.get(start..).unwrap_or_default();
    let header = &header[..len.min(header.len())];
    let (mut depth, mut deepest) = (0usize, 0usize);
    for b in header {
        match b {
            b'[' | b'(' | b'{' => {
                depth += 1;
                deepest = deepest.max(depth);
            }
            b']' | b')' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    if deepest > MAX_HEADER_NESTING {
        return Err(format_error(
            path,
            format!("its NPY header nests brackets {deepest} deep (an array's header nests 2): the file is damaged, write it again with numpy.save"),
        ));
    }
    Ok(())
}

/// The array in `bytes` as `(T, 20)` f32, whichever of the accepted forms it has.
fn parse(bytes: &[u8], path: &Path) -> Result<Array2<f32>> {
    check_header(bytes, path)?;
    let two_d = |a: Array2<f32>| -> Result<Array2<f32>> {
        if a.ncols() == 2 * JOINT_COUNT {
            Ok(a)
        } else {
            Err(SkeletonError::FileShape {
                path: path.to_path_buf(),
                what: format!(
                    "NPY array is ({}, {}), expected (frames, 20): x, y of the 10 joints",
                    a.nrows(),
                    a.ncols()
                ),
            })
        }
    };
    let three_d = |a: Array3<f32>| -> Result<Array2<f32>> {
        let (t, j, c) = a.dim();
        if (j, c) != (JOINT_COUNT, 2) {
            return Err(SkeletonError::FileShape {
                path: path.to_path_buf(),
                what: format!(
                    "NPY array is ({t}, {j}, {c}), expected (frames, 20) or (frames, 10, 2)"
                ),
            });
        }
        a.as_standard_layout()
            .to_shape((t, 2 * JOINT_COUNT))
            .map(|v| v.to_owned())
            .map_err(|e| format_error(path, e.to_string()))
    };
    let first_error = match Array2::<f32>::read_npy(bytes) {
        Ok(a) => return two_d(a),
        Err(e) => e,
    };
    if let Ok(a) = Array2::<f64>::read_npy(bytes) {
        return two_d(a.mapv(|v| v as f32));
    }
    if let Ok(a) = Array3::<f32>::read_npy(bytes) {
        return three_d(a);
    }
    if let Ok(a) = Array3::<f64>::read_npy(bytes) {
        return three_d(a.mapv(|v| v as f32));
    }
    Err(format_error(
        path,
        format!("not a float32 (frames, 20) NPY array ({first_error})"),
    ))
}

pub(crate) fn read(bytes: &[u8], fps: f64, path: &Path) -> Result<Motion> {
    let mut flat = parse(bytes, path)?;
    if !flat.is_standard_layout() {
        flat = flat.as_standard_layout().into_owned();
    }
    let t = flat.nrows();
    if t == 0 {
        return Err(SkeletonError::Empty {
            path: path.to_path_buf(),
        });
    }
    if let Some(((row, col), v)) = flat.indexed_iter().find(|(_, v)| !v.is_finite()) {
        return Err(SkeletonError::NonFinite {
            path: path.to_path_buf(),
            location: format!(
                "frame {row}, joint {}, coordinate {} = {v}",
                Joint::ALL[col / 2].name(),
                ["x", "y"][col % 2]
            ),
        });
    }
    if !(fps.is_finite() && fps > 0.0) {
        return Err(SkeletonError::InvalidFps(fps));
    }
    let frames = flat
        .into_shape_with_order((t, JOINT_COUNT, 2))
        .map_err(|e| format_error(path, e.to_string()))?;
    Motion::new(fps, frames)
}
