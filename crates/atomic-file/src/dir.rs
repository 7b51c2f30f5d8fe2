//! Folder outputs (OpenPose keypoint files, PNG frames): filled under a temporary name, then
//! renamed into place.

use std::io::{Error, ErrorKind};
use std::path::Path;

use crate::destination::is_stdout;
use crate::file::{make_ordinary, parent_dir, AtomicWriteError};

fn refused(reason: String) -> Error {
    Error::new(ErrorKind::InvalidInput, reason)
}

/// `true` when `dir` holds only files whose names `owned` accepts (or nothing).
fn holds_only_owned(dir: &Path, owned: &dyn Fn(&str) -> bool) -> std::io::Result<bool> {
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let is_file = entry.file_type()?.is_file();
        if !(is_file && owned(&entry.file_name().to_string_lossy())) {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Creates folder `dir` with `fill` atomically: `fill` writes into a temporary folder beside
/// `dir`, which is then renamed to `dir`. An existing `dir` is replaced as a whole (so no
/// stale file of a longer earlier run survives) but only when it holds nothing but files
/// whose names `owned` accepts, so no user file is ever deleted. `-` (standard output) cannot
/// hold a folder and is refused, as are a missing parent folder and an existing file.
///
/// Refusals are [`AtomicWriteError::Io`] errors of kind `InvalidInput` whose message says
/// what to do.
///
/// ```
/// let parent = tempfile::tempdir()?;
/// let frames = parent.path().join("frames");
/// let is_frame = |name: &str| name.starts_with("frame_") && name.ends_with(".png");
/// atomic_file::replace_dir_atomically(&frames, &is_frame, |tmp| {
///     std::fs::write(tmp.join("frame_000000.png"), b"png")
/// })?;
/// assert!(frames.join("frame_000000.png").exists());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn replace_dir_atomically<E>(
    dir: &Path,
    owned: &dyn Fn(&str) -> bool,
    fill: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<(), AtomicWriteError<E>> {
    let io = AtomicWriteError::Io;
    if is_stdout(dir) {
        return Err(io(refused(
            "standard output (-) cannot hold a folder of files; give a folder name".into(),
        )));
    }
    let parent = parent_dir(dir);
    if !parent.is_dir() {
        return Err(io(refused(format!(
            "folder {} does not exist; create it first",
            parent.display()
        ))));
    }
    if dir.exists() {
        if !dir.is_dir() {
            return Err(io(refused(
                "a file with this name exists; choose a folder name".into(),
            )));
        }
        if !holds_only_owned(dir, owned).map_err(io)? {
            return Err(io(refused(
                "the folder exists and holds other files; choose a new or empty folder".into(),
            )));
        }
    }
    let tmp = tempfile::Builder::new()
        .prefix(".violin-skeleton-dir-")
        .tempdir_in(&parent)
        .map_err(io)?;
    fill(tmp.path()).map_err(AtomicWriteError::Write)?;
    make_ordinary(tmp.path(), true);
    if dir.exists() {
        // Move the old folder aside (a fresh temporary name), move the new one in, then
        // delete the old one; on failure put the old one back.
        let aside = tempfile::Builder::new()
            .prefix(".violin-skeleton-old-")
            .tempdir_in(&parent)
            .map_err(io)?;
        let aside_path = aside.path().join("old");
        std::fs::rename(dir, &aside_path).map_err(io)?;
        if let Err(e) = std::fs::rename(tmp.path(), dir) {
            // Best effort: the original error is the one to report.
            let _ = std::fs::rename(&aside_path, dir);
            return Err(io(e));
        }
        let _ = tmp.keep();
        drop(aside); // removes the old folder
    } else {
        std::fs::rename(tmp.path(), dir).map_err(io)?;
        let _ = tmp.keep();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_shorter_run_leaves_no_stale_files_and_user_files_are_kept() {
        let parent = tempfile::tempdir().unwrap();
        let out = parent.path().join("frames");
        let owned = |n: &str| n.ends_with(".png");
        let fill = |k: usize| {
            move |d: &Path| -> std::io::Result<()> {
                for i in 0..k {
                    std::fs::write(d.join(format!("f{i}.png")), b"x")?;
                }
                Ok(())
            }
        };
        replace_dir_atomically(&out, &owned, fill(3)).unwrap();
        replace_dir_atomically(&out, &owned, fill(1)).unwrap();
        assert_eq!(names(&out), vec!["f0.png"]);
        assert_eq!(names(parent.path()), vec!["frames"]);

        std::fs::write(out.join("notes.txt"), b"mine").unwrap();
        let err = replace_dir_atomically(&out, &owned, fill(2)).unwrap_err();
        assert!(err.to_string().contains("holds other files"), "{err}");
        assert_eq!(names(&out), vec!["f0.png", "notes.txt"]);
    }

    #[test]
    fn failures_and_refusals_leave_nothing_behind() {
        let parent = tempfile::tempdir().unwrap();
        let out = parent.path().join("pose");
        let r = replace_dir_atomically(&out, &|_| true, |_| Err::<(), _>("boom"));
        assert!(matches!(r, Err(AtomicWriteError::Write("boom"))));
        assert!(names(parent.path()).is_empty());
        let ok = |_: &Path| Ok::<(), String>(());
        assert!(replace_dir_atomically(Path::new("-"), &|_| true, ok).is_err());
        assert!(!Path::new("-").exists());
        let file = parent.path().join("file");
        std::fs::write(&file, b"x").unwrap();
        assert!(replace_dir_atomically(&file, &|_| true, ok).is_err());
        assert!(replace_dir_atomically(&file.join("sub"), &|_| true, ok).is_err());
    }
}
