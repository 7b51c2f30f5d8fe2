//! CSV: `frame,time_s,nose_x,nose_y,…,l_hip_y`, one row per frame (2-D track only).

use std::io::{Read, Write};
use std::path::Path;

use ndarray::Array3;

use super::check::format_error;
use crate::error::{Result, SkeletonError};
use crate::joint::{Joint, JOINT_COUNT};
use crate::motion::Motion;

/// The CSV header's column names, in the order written.
fn header() -> Vec<String> {
    let mut cols = vec!["frame".to_string(), "time_s".to_string()];
    for j in Joint::ALL {
        cols.push(format!("{}_x", j.name()));
        cols.push(format!("{}_y", j.name()));
    }
    cols
}

/// Writes the 2-D track of `motion` as CSV to `writer` (`time_s` = frame / fps).
///
/// ```
/// use ndarray::Array3;
/// let m = skeleton::Motion::new(30.0, Array3::zeros((3, 10, 2)))?;
/// let mut bytes = Vec::new();
/// skeleton::formats::write_csv(&m, &mut bytes)?;
/// let text = String::from_utf8_lossy(&bytes);
/// assert!(text.starts_with("frame,time_s,nose_x,nose_y,neck_x"));
/// assert_eq!(text.lines().count(), 4);
/// assert_eq!(skeleton::formats::read_csv_from(bytes.as_slice())?, m);
/// # Ok::<(), skeleton::SkeletonError>(())
/// ```
pub fn write_csv(motion: &Motion, writer: impl Write) -> Result<()> {
    let path = super::check::memory_path();
    super::check::check_writable(motion, &path, false)?;
    write(motion, writer, &path)
}

pub(crate) fn write(motion: &Motion, mut writer: impl Write, path: &Path) -> Result<()> {
    let io = |e: std::io::Error| SkeletonError::Io {
        path: path.to_path_buf(),
        source: e,
    };
    writeln!(writer, "{}", header().join(",")).map_err(io)?;
    let mut line = String::with_capacity(256);
    for (t, frame) in motion.frames().outer_iter().enumerate() {
        use std::fmt::Write as _;
        line.clear();
        let _ = write!(line, "{t},{}", t as f64 / motion.fps());
        for v in frame.iter() {
            let _ = write!(line, ",{v}");
        }
        line.push('\n');
        writer.write_all(line.as_bytes()).map_err(io)?;
    }
    Ok(())
}

/// Reads CSV from `reader`: columns by header name (any order; all 22 required, no others),
/// frames numbered 0, 1, 2, …, fps from the `time_s` column (30 for a single row).
pub fn read_csv_from(reader: impl Read) -> Result<Motion> {
    let (bytes, path) = super::check::read_all(reader)?;
    read(&bytes, &path)
}

/// Where each header column goes: frame, time, or (joint, coordinate).
#[derive(Clone, Copy)]
enum Column {
    Frame,
    Time,
    Coord(usize, usize),
}

fn columns(path: &Path, head: &str) -> Result<Vec<Column>> {
    let known = header();
    let mut seen = vec![false; known.len()];
    let mut cols = Vec::new();
    for name in head.split(',').map(str::trim) {
        let Some(i) = known.iter().position(|k| k == name) else {
            return Err(SkeletonError::UnknownJoint {
                path: path.to_path_buf(),
                name: format!("{name} (CSV column)"),
            });
        };
        if std::mem::replace(&mut seen[i], true) {
            return Err(format_error(path, format!("column {name} appears twice")));
        }
        cols.push(match i {
            0 => Column::Frame,
            1 => Column::Time,
            k => Column::Coord((k - 2) / 2, (k - 2) % 2),
        });
    }
    if let Some(i) = seen.iter().position(|s| !s) {
        return Err(SkeletonError::MissingField {
            path: path.to_path_buf(),
            field: known[i].clone(),
            hint: "the header must be frame,time_s,nose_x,nose_y,…,l_hip_y".into(),
        });
    }
    Ok(cols)
}

/// The frame rate implied by evenly spaced `times` (snapped to an integer within 1e-6).
fn fps_from_times(path: &Path, times: &[f64]) -> Result<f64> {
    let n = times.len();
    if n < 2 {
        return Ok(super::check::DEFAULT_FPS);
    }
    let span = times[n - 1] - times[0];
    let raw = (n - 1) as f64 / span;
    if !(raw.is_finite() && raw > 0.0) {
        return Err(format_error(path, "time_s must increase from row to row"));
    }
    let fps = if (raw - raw.round()).abs() < 1e-6 * raw {
        raw.round()
    } else {
        raw
    };
    for (t, time) in times.iter().enumerate() {
        let expected = times[0] + t as f64 / fps;
        if (time - expected).abs() > 0.25 / fps {
            return Err(format_error(
                path,
                format!("time_s of frame {t} is {time}, expected {expected:.6} at {fps} fps: rows must be evenly spaced in time"),
            ));
        }
    }
    Ok(fps)
}

pub(crate) fn read(bytes: &[u8], path: &Path) -> Result<Motion> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| format_error(path, format!("not UTF-8 text: {e}")))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, head)) = lines.next() else {
        return Err(SkeletonError::Empty {
            path: path.to_path_buf(),
        });
    };
    let cols = columns(path, head)?;
    let mut coords: Vec<f32> = Vec::new();
    let mut times = Vec::new();
    let mut row = [0.0f32; 2 * JOINT_COUNT];
    for (line_index, line) in lines {
        let line_no = line_index + 1;
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != cols.len() {
            return Err(SkeletonError::FileShape {
                path: path.to_path_buf(),
                what: format!(
                    "line {line_no} has {} fields, the header has {}",
                    fields.len(),
                    cols.len()
                ),
            });
        }
        let frame_index = times.len();
        for (field, col) in fields.iter().zip(&cols) {
            let value: f64 = field.parse().map_err(|_| {
                format_error(path, format!("line {line_no}: {field:?} is not a number"))
            })?;
            match *col {
                Column::Frame => {
                    if value != frame_index as f64 {
                        return Err(format_error(
                            path,
                            format!("line {line_no}: frame is {field}, expected {frame_index} (frames must count 0, 1, 2, …)"),
                        ));
                    }
                }
                Column::Time => times.push(value),
                Column::Coord(j, c) => {
                    let v = value as f32;
                    if !v.is_finite() {
                        return Err(SkeletonError::NonFinite {
                            path: path.to_path_buf(),
                            location: format!(
                                "line {line_no}, column {}_{}",
                                Joint::ALL[j].name(),
                                ["x", "y"][c]
                            ),
                        });
                    }
                    row[2 * j + c] = v;
                }
            }
        }
        coords.extend_from_slice(&row);
    }
    if times.is_empty() {
        return Err(SkeletonError::Empty {
            path: path.to_path_buf(),
        });
    }
    let fps = fps_from_times(path, &times)?;
    let frames = Array3::from_shape_vec((times.len(), JOINT_COUNT, 2), coords)
        .map_err(|e| format_error(path, e.to_string()))?;
    Motion::new(fps, frames)
}
