//! The output contract, checked before anything is read or written: no output may be one of
//! the inputs (however spelled: `..`, symbolic or hard links), no two outputs may be the same
//! file, and `-` (standard output) is accepted only for single-file outputs.

use std::path::{Path, PathBuf};

use crate::error::CliError;

/// One path of a command line and the flag that gave it (`"input"` for a positional one).
#[derive(Debug, Clone, Copy)]
pub struct NamedPath<'a> {
    /// The flag, e.g. `-o` or `--preview`.
    pub flag: &'a str,
    /// The path as given.
    pub path: &'a Path,
}

/// Shorthand for a [`NamedPath`].
pub fn named<'a>(flag: &'a str, path: &'a Path) -> NamedPath<'a> {
    NamedPath { flag, path }
}

/// The path made absolute with its folder resolved (symbolic links, `..`), for paths that
/// may not exist yet; `None` when the folder does not exist either.
fn resolved(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = std::fs::canonicalize(path) {
        return Some(p);
    }
    let name = path.file_name()?;
    let parent = atomic_file::parent_dir(path);
    std::fs::canonicalize(parent).ok().map(|p| p.join(name))
}

/// `true` when writing `a` would write `b`.
fn same_target(a: &Path, b: &Path) -> bool {
    if atomic_file::is_stdout(a) || atomic_file::is_stdout(b) {
        return atomic_file::is_stdout(a) && atomic_file::is_stdout(b);
    }
    atomic_file::same_file(a, b)
        || matches!((resolved(a), resolved(b)), (Some(x), Some(y)) if x == y)
}

/// Refuses (exit 2, nothing written) an output that is one of `inputs` or another output.
pub fn check_outputs(inputs: &[NamedPath<'_>], outputs: &[NamedPath<'_>]) -> Result<(), CliError> {
    for (k, out) in outputs.iter().enumerate() {
        for input in inputs {
            if same_target(out.path, input.path) {
                return Err(CliError::Usage(format!(
                    "{} {}: is the same file as the {} {}; writing it would destroy the input; choose another output name",
                    out.flag,
                    out.path.display(),
                    input.flag,
                    input.path.display()
                )));
            }
        }
        for other in &outputs[..k] {
            if same_target(out.path, other.path) {
                return Err(CliError::Usage(format!(
                    "{} {}: is also the output of {}; give each output its own name",
                    out.flag,
                    out.path.display(),
                    other.flag
                )));
            }
        }
    }
    Ok(())
}

/// Refuses `-` (standard output) for an output that is a folder of files.
pub fn refuse_stdout_folder(out: NamedPath<'_>, what: &str, instead: &str) -> Result<(), CliError> {
    if atomic_file::is_stdout(out.path) {
        return Err(CliError::Usage(format!(
            "{} -: {what} is a folder of files and cannot go to standard output; {instead}",
            out.flag
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_that_are_inputs_or_each_other_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let wav = dir.path().join("rec.wav");
        std::fs::write(&wav, b"RIFF").unwrap();
        let dotted = dir.path().join(".").join("rec.wav");
        let input = [named("input", &wav)];
        let err = check_outputs(&input, &[named("-o", &dotted)]).unwrap_err();
        assert_eq!(err.exit_code(), 2);
        assert!(err.to_string().contains("destroy the input"), "{err}");

        let a = dir.path().join("m.json");
        let b = dir.path().join("sub").join("..").join("m.json");
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let err = check_outputs(&input, &[named("-o", &a), named("--analysis-out", &b)]);
        assert!(err
            .unwrap_err()
            .to_string()
            .contains("also the output of -o"));

        let stdout = Path::new("-");
        assert!(check_outputs(&input, &[named("-o", stdout), named("--preview", &a)]).is_ok());
        assert!(check_outputs(&input, &[named("-o", stdout), named("--preview", stdout)]).is_err());
        assert!(refuse_stdout_folder(named("-o", stdout), "OpenPose output", "x").is_err());
        assert!(refuse_stdout_folder(named("-o", &a), "OpenPose output", "x").is_ok());
    }
}
