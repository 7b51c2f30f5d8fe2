//! What kind of thing an output path names, and whether two paths are one file.

use std::path::Path;

/// How an output path is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Destination {
    /// `-`: standard output, written directly.
    Stdout,
    /// An existing FIFO, character or block device or socket: opened and written directly,
    /// never replaced by a regular file.
    Special,
    /// Anything else: a regular file, written beside the target and renamed over it.
    Regular,
}

/// `true` when `path` is `-`, the conventional name of standard output.
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// How `path` is written (see [`Destination`]).
///
/// ```
/// use atomic_file::{destination, Destination};
/// use std::path::Path;
/// assert_eq!(destination(Path::new("-")), Destination::Stdout);
/// assert_eq!(destination(Path::new("new-file.json")), Destination::Regular);
/// # #[cfg(unix)]
/// assert_eq!(destination(Path::new("/dev/null")), Destination::Special);
/// ```
pub fn destination(path: &Path) -> Destination {
    if is_stdout(path) {
        return Destination::Stdout;
    }
    match std::fs::metadata(path) {
        Ok(m) if is_special(&m.file_type()) => Destination::Special,
        _ => Destination::Regular,
    }
}

#[cfg(unix)]
fn is_special(t: &std::fs::FileType) -> bool {
    use std::os::unix::fs::FileTypeExt;
    t.is_fifo() || t.is_char_device() || t.is_block_device() || t.is_socket()
}

#[cfg(not(unix))]
fn is_special(t: &std::fs::FileType) -> bool {
    !t.is_file() && !t.is_dir()
}

/// `true` when `a` and `b` are the same existing file or folder, however they are spelled:
/// through `..`, symbolic links or hard links (same device and inode). A path that does not
/// exist yet is never the same as another, and `-` is never a file.
///
/// ```
/// let dir = tempfile::tempdir()?;
/// let a = dir.path().join("take.wav");
/// std::fs::write(&a, b"RIFF")?;
/// let b = dir.path().join(".").join("take.wav");
/// assert!(atomic_file::same_file(&a, &b));
/// assert!(!atomic_file::same_file(&a, &dir.path().join("motion.json")));
/// # Ok::<(), std::io::Error>(())
/// ```
pub fn same_file(a: &Path, b: &Path) -> bool {
    if is_stdout(a) || is_stdout(b) {
        return false;
    }
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    same_identity(a, &ma, b, &mb)
}

#[cfg(unix)]
fn same_identity(_: &Path, ma: &std::fs::Metadata, _: &Path, mb: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    ma.dev() == mb.dev() && ma.ino() == mb.ino()
}

#[cfg(not(unix))]
fn same_identity(a: &Path, _: &std::fs::Metadata, b: &Path, _: &std::fs::Metadata) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn links_and_spellings_are_the_same_file() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("in.wav");
        std::fs::write(&a, b"x").unwrap();
        let sym = dir.path().join("sym.wav");
        std::os::unix::fs::symlink(&a, &sym).unwrap();
        let hard = dir.path().join("hard.wav");
        std::fs::hard_link(&a, &hard).unwrap();
        let sub = dir.path().join("sub");
        std::fs::create_dir(&sub).unwrap();
        let dotted = sub.join("..").join("in.wav");
        for other in [&sym, &hard, &dotted] {
            assert!(same_file(&a, other), "{}", other.display());
        }
        let c = dir.path().join("copy.wav");
        std::fs::write(&c, b"x").unwrap();
        assert!(!same_file(&a, &c));
        assert!(!same_file(&a, Path::new("-")));
        assert!(same_file(dir.path(), &sub.join("..")));
    }

    #[cfg(unix)]
    #[test]
    fn fifo_is_special() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .is_ok_and(|s| s.success());
        assert!(made, "mkfifo failed");
        assert_eq!(destination(&fifo), Destination::Special);
        assert_eq!(destination(dir.path()), Destination::Regular);
    }
}
