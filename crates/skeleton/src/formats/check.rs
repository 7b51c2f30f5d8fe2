//! What every format shares: the default frame rate, the in-memory path label, format
//! errors, reading a whole reader, and the checks before writing.

use std::path::{Path, PathBuf};

use ndarray::Array3;

use crate::error::{Result, SkeletonError};
use crate::joint::Joint;
use crate::motion::{InstrumentPoint, Motion};

/// Frame rate assumed when a format does not store one (NPY, OpenPose, a one-row CSV).
pub const DEFAULT_FPS: f64 = 30.0;

/// The label used in errors from the in-memory readers and writers.
pub(crate) const MEMORY: &str = "<memory>";

/// Fails on an empty motion or a non-finite value in the tracks a format writes.
pub(crate) fn check_writable(motion: &Motion, path: &Path, all_tracks: bool) -> Result<()> {
    if motion.is_empty() {
        return Err(SkeletonError::Empty {
            path: path.to_path_buf(),
        });
    }
    check_finite(motion.frames(), "frames", path, true)?;
    if let Some(p) = motion.performer() {
        for part in crate::PerformerPart::ALL {
            let name = format!("performer.{}", part.name());
            check_finite(p.track(part), &name, path, false)?;
            if let Some(t) = p.track_3d(part).filter(|_| all_tracks) {
                check_finite(t, &format!("{name}_3d"), path, false)?;
            }
        }
    }
    if all_tracks {
        if let Some(t) = motion.frames_3d() {
            check_finite(t, "frames_3d", path, true)?;
        }
        if let Some(t) = motion.instrument() {
            check_finite(t, "instrument", path, false)?;
        }
        if let Some(t) = motion.instrument_3d() {
            check_finite(t, "instrument_3d", path, false)?;
        }
    }
    Ok(())
}

/// Fails naming the first non-finite value of a `(T, points, dims)` track.
fn check_finite(track: &Array3<f32>, name: &str, path: &Path, joints: bool) -> Result<()> {
    match track.indexed_iter().find(|(_, v)| !v.is_finite()) {
        None => Ok(()),
        Some(((t, p, c), v)) => Err(SkeletonError::NonFinite {
            path: path.to_path_buf(),
            location: format!(
                "{name}: frame {t}, {} {}{}, coordinate {} = {v}",
                if joints { "joint" } else { "point" },
                if name.starts_with("performer") {
                    ""
                } else {
                    point_name(p, joints)
                },
                if name.starts_with("performer") {
                    p.to_string()
                } else {
                    String::new()
                },
                ["x", "y", "z"].get(c).copied().unwrap_or("?")
            ),
        }),
    }
}

/// The name of point `p` of a joint or instrument track.
fn point_name(p: usize, joints: bool) -> &'static str {
    if joints {
        Joint::ALL.get(p).map_or("?", |j| j.name())
    } else {
        InstrumentPoint::ALL.get(p).map_or("?", |i| i.name())
    }
}

/// A path for error messages of the in-memory readers and writers.
pub(crate) fn memory_path() -> PathBuf {
    PathBuf::from(MEMORY)
}

/// A format error about the file at `path`.
pub(crate) fn format_error(path: &Path, reason: impl Into<String>) -> SkeletonError {
    SkeletonError::Format {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}

/// Everything `reader` holds, for the in-memory readers, with the path their errors name.
pub(crate) fn read_all(mut reader: impl std::io::Read) -> Result<(Vec<u8>, PathBuf)> {
    let path = memory_path();
    let mut bytes = Vec::new();
    match reader.read_to_end(&mut bytes) {
        Ok(_) => Ok((bytes, path)),
        Err(source) => Err(SkeletonError::Io { path, source }),
    }
}
