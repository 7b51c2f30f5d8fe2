//! Reading whole files, and atomic writes of files and directories.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::check::format_error;
use crate::error::{Result, SkeletonError};

fn io_error(path: &Path, source: std::io::Error) -> SkeletonError {
    SkeletonError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The bytes of a file; a directory, a missing or an empty file is a clear error.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>> {
    if path.is_dir() {
        return Err(format_error(
            path,
            "is a directory; pass a motion file (or read it as an OpenPose directory)",
        ));
    }
    let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
    if bytes.is_empty() {
        return Err(format_error(path, "file is empty (0 bytes)"));
    }
    Ok(bytes)
}

/// The directory a new file or directory at `path` goes into; it must exist.
fn parent_dir(path: &Path) -> Result<PathBuf> {
    let dir = atomic_file::parent_dir(path);
    if !dir.is_dir() {
        return Err(format_error(
            path,
            format!(
                "cannot write: folder {} does not exist; create it first",
                dir.display()
            ),
        ));
    }
    Ok(dir)
}

/// Writes `path` through `write`, atomically: to a temporary file beside it, then renamed.
pub(crate) fn write_file(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<()>,
) -> Result<()> {
    if path.is_dir() {
        return Err(format_error(
            path,
            "cannot write: is a directory; give a file name",
        ));
    }
    parent_dir(path)?;
    atomic_file::write_atomically(path, write).map_err(|e| match e {
        atomic_file::AtomicWriteError::Io(e) => io_error(path, e),
        atomic_file::AtomicWriteError::Write(e) => e,
    })
}

/// Creates directory `dir` with `fill` atomically ([`atomic_file::replace_dir_atomically`]):
/// an existing `dir` is replaced as a whole only when it holds nothing but
/// `*_keypoints.json` files (so no user file is ever deleted and no stale frame survives).
pub(crate) fn write_dir(dir: &Path, fill: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let owned = |name: &str| name.ends_with("_keypoints.json");
    atomic_file::replace_dir_atomically(dir, &owned, fill).map_err(|e| match e {
        atomic_file::AtomicWriteError::Io(e) if e.kind() == std::io::ErrorKind::InvalidInput => {
            format_error(dir, format!("cannot write an OpenPose folder: {e}"))
        }
        atomic_file::AtomicWriteError::Io(e) => io_error(dir, e),
        atomic_file::AtomicWriteError::Write(e) => e,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_write_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.json");
        let err = write_file(&path, |_| Err(format_error(&path, "boom"))).unwrap_err();
        assert!(err.to_string().contains("boom"));
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);

        let sub = dir.path().join("pose");
        assert!(write_dir(&sub, |_| Err(format_error(&sub, "boom"))).is_err());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[cfg(unix)]
    #[test]
    fn outputs_are_ordinary_files_and_directories() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("m.json");
        write_file(&file, |w| {
            w.write_all(b"{}").map_err(|e| io_error(&file, e))
        })
        .unwrap();
        let mode = std::fs::metadata(&file).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o644);
        let sub = dir.path().join("pose");
        write_dir(&sub, |_| Ok(())).unwrap();
        let mode = std::fs::metadata(&sub).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o755);
    }

    #[test]
    fn directory_is_replaced_only_when_it_holds_keypoint_files() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("pose");
        let fill = |name: &'static str| {
            move |d: &Path| {
                std::fs::write(d.join(name), b"{}").map_err(|e| io_error(d, e))?;
                Ok(())
            }
        };
        write_dir(&out, fill("a_000000000000_keypoints.json")).unwrap();
        write_dir(&out, fill("b_000000000000_keypoints.json")).unwrap();
        let names: Vec<_> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        assert_eq!(names, vec!["b_000000000000_keypoints.json"]);
        // Only `pose` remains in the parent: no temporary left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);

        std::fs::write(out.join("notes.txt"), b"mine").unwrap();
        let err = write_dir(&out, fill("c_000000000000_keypoints.json")).unwrap_err();
        assert!(err.to_string().contains("holds other files"), "{err}");
        assert!(out.join("notes.txt").exists());
    }

    #[test]
    fn missing_parent_and_empty_file_are_clear_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nope").join("m.json");
        let err = write_file(&path, |_| Ok(())).unwrap_err();
        assert!(err.to_string().contains("does not exist"), "{err}");
        let empty = dir.path().join("e.json");
        std::fs::write(&empty, b"").unwrap();
        assert!(read_file(&empty).unwrap_err().to_string().contains("empty"));
    }
}
