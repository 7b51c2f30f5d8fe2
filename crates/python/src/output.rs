//! Writing one output file atomically, refusing a directory or a missing folder with a
//! message that names the path.

use std::path::Path;

use crate::errors::{PyApiError, Result};

/// Checks that `path` can be a new or replaced file: not a directory, in an existing folder.
pub fn check_file_target(path: &Path) -> Result<()> {
    let refuse = |reason: String| PyApiError::Output {
        path: path.to_path_buf(),
        reason,
    };
    if path.is_dir() {
        return Err(refuse("is a directory; give a file name".into()));
    }
    let dir = atomic_file::parent_dir(path);
    if !dir.is_dir() {
        return Err(refuse(format!(
            "folder {} does not exist; create it first",
            dir.display()
        )));
    }
    Ok(())
}

/// Writes `bytes` to `path` atomically (a temporary file beside it, then renamed).
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    check_file_target(path)?;
    atomic_file::write_bytes_atomically(path, bytes).map_err(|e| PyApiError::Output {
        path: path.to_path_buf(),
        reason: format!("cannot write there ({e})"),
    })
}
