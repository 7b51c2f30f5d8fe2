//! Atomic file writes: a temporary file in the target's folder, renamed into place at the
//! end, so a failure never leaves a half-written picture.

use std::io::{BufWriter, Write};
use std::path::Path;

use crate::error::{RenderError, Result};

/// Writes `path` through `write`, atomically.
pub(crate) fn write_file_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<&mut std::fs::File>) -> Result<()>,
) -> Result<()> {
    let io = |source: std::io::Error| RenderError::Io {
        path: path.to_path_buf(),
        source,
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut tmp = tempfile::Builder::new()
        .prefix(".skeleton-render-")
        .suffix(".tmp")
        .tempfile_in(dir)
        .map_err(io)?;
    {
        let mut w = BufWriter::new(tmp.as_file_mut());
        write(&mut w).map_err(|e| match e {
            RenderError::Write(source) => io(source),
            other => other,
        })?;
        w.flush().map_err(io)?;
    }
    // Temporary files are private (0600); the result should be readable like any file.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(0o644))
            .map_err(io)?;
    }
    tmp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}
