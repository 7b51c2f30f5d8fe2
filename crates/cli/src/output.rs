//! Writing outputs atomically: to a temporary file beside the target, then renamed, so a
//! failure never leaves a half-written file.

use std::io::Write;
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
    let dir = atomic_file::parent_dir(path);
    if !dir.is_dir() {
        return Err(unwritable(format!(
            "folder {} does not exist; create it first",
            dir.display()
        )));
    }
    atomic_file::write_atomically(path, write).map_err(|e| match e {
        atomic_file::AtomicWriteError::Io(e) => unwritable(format!("cannot write there ({e})")),
        atomic_file::AtomicWriteError::Write(reason) => unwritable(reason),
    })
}
