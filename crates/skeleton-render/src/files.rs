//! Atomic file writes through the shared `atomic-file` crate, so a failure never leaves a
//! half-written picture.

use std::io::Write;
use std::path::Path;

use crate::error::{RenderError, Result};

/// Writes `path` through `write`, atomically.
pub(crate) fn write_file_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<()>,
) -> Result<()> {
    let io = |source: std::io::Error| RenderError::Io {
        path: path.to_path_buf(),
        source,
    };
    atomic_file::write_atomically(path, write).map_err(|e| match e {
        atomic_file::AtomicWriteError::Io(source) => io(source),
        atomic_file::AtomicWriteError::Write(RenderError::Write(source)) => io(source),
        atomic_file::AtomicWriteError::Write(other) => other,
    })
}
