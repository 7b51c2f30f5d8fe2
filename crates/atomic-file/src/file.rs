//! Writing one file: atomically for a regular file, directly for `-` and special files.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::destination::{destination, Destination};

/// Why an atomic write failed: the file system, or the caller's own writer.
#[derive(Debug)]
pub enum AtomicWriteError<E> {
    /// Creating, flushing or renaming the file failed.
    Io(std::io::Error),
    /// The writer closure returned an error.
    Write(E),
}

impl<E: std::fmt::Display> std::fmt::Display for AtomicWriteError<E> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AtomicWriteError::Io(e) => write!(f, "{e}"),
            AtomicWriteError::Write(e) => write!(f, "{e}"),
        }
    }
}

impl<E: std::fmt::Debug + std::fmt::Display> std::error::Error for AtomicWriteError<E> {}

/// The folder a file at `path` goes into (`.` for a bare file name).
pub fn parent_dir(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Writes `path` through `write`: atomically for a regular file, directly for `-` (standard
/// output) and for an existing special file (see the crate documentation).
pub fn write_atomically<E>(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<(), E>,
) -> Result<(), AtomicWriteError<E>> {
    match destination(path) {
        Destination::Stdout => {
            let stdout = std::io::stdout();
            let mut w = BufWriter::new(stdout.lock());
            write(&mut w).map_err(AtomicWriteError::Write)?;
            return w.flush().map_err(AtomicWriteError::Io);
        }
        Destination::Special => {
            let file = std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(AtomicWriteError::Io)?;
            let mut w = BufWriter::new(file);
            write(&mut w).map_err(AtomicWriteError::Write)?;
            return w.flush().map_err(AtomicWriteError::Io);
        }
        Destination::Regular => {}
    }
    let tmp = tempfile::Builder::new()
        .prefix(".violin-skeleton-")
        .suffix(".tmp")
        .tempfile_in(parent_dir(path))
        .map_err(AtomicWriteError::Io)?;
    {
        let mut w = BufWriter::new(tmp.as_file());
        write(&mut w).map_err(AtomicWriteError::Write)?;
        w.flush().map_err(AtomicWriteError::Io)?;
    }
    make_ordinary(tmp.path(), false);
    tmp.persist(path)
        .map_err(|e| AtomicWriteError::Io(e.error))?;
    Ok(())
}

/// [`write_atomically`] for bytes already in memory.
pub fn write_bytes_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomically(path, |w| w.write_all(bytes)).map_err(|e| match e {
        AtomicWriteError::Io(e) | AtomicWriteError::Write(e) => e,
    })
}

/// Gives a file (0644) or folder (0755) ordinary permissions, for callers that build a
/// folder under a temporary name and rename it into place. Best effort: on failure the
/// private mode stays.
pub fn make_ordinary(path: &Path, is_dir: bool) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = if is_dir { 0o755 } else { 0o644 };
        let _ = std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode));
    }
    #[cfg(not(unix))]
    let _ = (path, is_dir);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failure_keeps_the_old_file_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        std::fs::write(&path, b"old").unwrap();
        let r = write_atomically(&path, |w| {
            w.write_all(b"half").map_err(|e| e.to_string())?;
            Err::<(), String>("writer failed".into())
        });
        assert!(matches!(r, Err(AtomicWriteError::Write(ref m)) if m == "writer failed"));
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[cfg(unix)]
    #[test]
    fn a_device_is_written_directly_and_never_replaced() {
        use std::os::unix::fs::FileTypeExt;
        // /dev/null takes the bytes and stays a character device.
        write_bytes_atomically(Path::new("/dev/null"), b"x").unwrap();
        assert!(std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device());
        // /dev/full refuses them: an error, and still a device.
        if Path::new("/dev/full").exists() {
            assert!(write_bytes_atomically(Path::new("/dev/full"), &[0u8; 1 << 16]).is_err());
            assert!(std::fs::metadata("/dev/full")
                .unwrap()
                .file_type()
                .is_char_device());
        }
    }

    #[test]
    fn missing_folder_is_an_io_error() {
        let r = write_bytes_atomically(Path::new("/no/such/folder/x.bin"), b"x");
        assert!(r.is_err());
    }

    #[cfg(unix)]
    #[test]
    fn outputs_are_ordinary_files() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.bin");
        write_bytes_atomically(&path, b"x").unwrap();
        let mode = std::fs::metadata(&path).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o644);
    }
}
