//! Writing outputs atomically: to a temporary file beside the target, then renamed, so a
//! failure never leaves a half-written file.

use std::io::{BufWriter, Write};
use std::path::Path;

use crate::error::CliError;

/// Writes `path` through `write`, atomically.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<(), String>,
) -> Result<(), CliError> {
    let unwritable = |reason: String| CliError::Output {
        path: path.to_path_buf(),
        reason,
    };
    if path.is_dir() {
        return Err(unwritable("is a directory; give a file name".into()));
    }
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(unwritable(format!(
            "folder {} does not exist; create it first",
            dir.display()
        )));
    }
    let tmp = tempfile::Builder::new()
        .prefix(".violin-skeleton-")
        .suffix(".tmp")
        .tempfile_in(dir)
        .map_err(|e| unwritable(format!("cannot create a file there ({e})")))?;
    {
        let mut w = BufWriter::new(tmp.as_file());
        write(&mut w).map_err(&unwritable)?;
        w.flush().map_err(|e| unwritable(e.to_string()))?;
    }
    #[cfg(unix)]
    {
        // tempfile creates 0600 files; an output is an ordinary file.
        use std::os::unix::fs::PermissionsExt;
        let _ = tmp
            .as_file()
            .set_permissions(std::fs::Permissions::from_mode(0o644));
    }
    tmp.persist(path)
        .map_err(|e| unwritable(format!("cannot rename into place ({})", e.error)))?;
    Ok(())
}
