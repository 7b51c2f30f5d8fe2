//! Batch mode: `generate DIR -o OUTDIR` and `analyze DIR -o OUTDIR` run every recording and
//! MIDI file under `DIR` in parallel with one [`violin_skeleton::Pipeline`] (its models
//! loaded once), mirror the folder layout in `OUTDIR`, keep going when a file fails, and write
//! `OUTDIR/batch_summary.json` (every failure with its reason). The command exits 1 when any
//! file failed.
//!
//! Files are found by extension (wav, flac, mp3, ogg, oga, mid, midi; any case); other files
//! are not music and are listed in the summary as skipped, not failed. A file with a music
//! extension that does not decode is a failure. `OUTDIR` is never searched for inputs.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use clap::Args;
use rayon::prelude::*;
use serde::Serialize;

use crate::error::CliError;
use crate::Reporter;

/// Extensions batch mode treats as recordings or MIDI files.
pub const MUSIC_EXTENSIONS: [&str; 7] = ["wav", "flac", "mp3", "ogg", "oga", "mid", "midi"];

/// The name of the summary batch mode writes in the output folder.
pub const SUMMARY_FILE: &str = "batch_summary.json";

/// The flags of batch mode (used when the input is a folder).
#[derive(Debug, Clone, Default, Args)]
pub struct BatchArgs {
    /// With a folder as input: files processed at once (default: one per CPU core). The
    /// models are loaded once and shared.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub jobs: Option<u32>,
    /// With a folder as input: leave files whose output already exists alone (resumes an
    /// interrupted run; outputs are written atomically, so an existing one is complete).
    #[arg(long)]
    pub skip_existing: bool,
}

/// One input of a batch and where its output goes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BatchItem {
    /// The recording or MIDI file.
    pub input: PathBuf,
    /// Its output (file, or folder for OpenPose).
    pub output: PathBuf,
}

/// What a batch found under its input folder.
#[derive(Debug, Default)]
pub struct BatchPlan {
    /// The files to process, in path order.
    pub items: Vec<BatchItem>,
    /// Files that are not music (by extension), relative to the input folder.
    pub not_music: Vec<PathBuf>,
}

/// Extensions of single files: an `-o` that has one names a file, not a batch's folder.
const FILE_EXTENSIONS: [&str; 14] = [
    "json", "csv", "npy", "bvh", "glb", "gif", "html", "mp4", "wav", "flac", "mp3", "ogg", "mid",
    "midi",
];

/// Refuses (exit 2) an output that cannot be a batch's output folder: `-` (standard output),
/// an existing file, a name with a file extension (`-o out.json`), or the input folder itself.
pub fn check_output_folder(input_dir: &Path, output_dir: &Path) -> Result<(), CliError> {
    crate::contract::refuse_stdout_folder(
        crate::contract::named("-o", output_dir),
        "a batch's output",
        "give a folder name",
    )?;
    let refuse = |why: &str| {
        Err(CliError::Usage(format!(
            "-o {}: {why}; with a folder as input, -o names the output folder",
            output_dir.display()
        )))
    };
    if output_dir.exists() && !output_dir.is_dir() {
        return refuse("is a file");
    }
    let file_like = output_dir.extension().is_some_and(|e| {
        let e = e.to_string_lossy().to_ascii_lowercase();
        FILE_EXTENSIONS.contains(&e.as_str())
    });
    if file_like && !output_dir.is_dir() {
        return refuse("looks like a file name");
    }
    if let (Ok(a), Ok(b)) = (
        std::fs::canonicalize(input_dir),
        std::fs::canonicalize(output_dir),
    ) {
        if a == b {
            return refuse("is the input folder (outputs would mix with the recordings)");
        }
    }
    Ok(())
}

/// `true` when `path` has one of [`MUSIC_EXTENSIONS`].
pub fn is_music(path: &Path) -> bool {
    path.extension().is_some_and(|e| {
        let e = e.to_string_lossy().to_ascii_lowercase();
        MUSIC_EXTENSIONS.contains(&e.as_str())
    })
}

/// Every file under `dir` (recursively; symbolic links to folders are not followed),
/// sorted, skipping the folder `exclude` (the output folder when it lies inside `dir`).
fn files_under(dir: &Path, exclude: Option<&Path>) -> Result<Vec<PathBuf>, CliError> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        if exclude.is_some_and(|x| std::fs::canonicalize(&d).is_ok_and(|c| c == x)) {
            continue;
        }
        let entries = std::fs::read_dir(&d).map_err(|e| CliError::Output {
            path: d.clone(),
            reason: format!("cannot list the folder ({e}); check that it is readable"),
        })?;
        for entry in entries.flatten() {
            let path = entry.path();
            match entry.file_type() {
                Ok(t) if t.is_dir() => stack.push(path),
                Ok(_) => found.push(path),
                Err(_) => found.push(path),
            }
        }
    }
    found.sort();
    Ok(found)
}

/// Plans a batch: every music file under `input_dir`, with its output in `output_dir` at the
/// same relative folder, named by its stem and `extension` (`None`: a folder named by the
/// stem). Two inputs that would share an output (`a.wav`, `a.flac`) keep their extension in
/// the name (`a.wav.json`, `a.flac.json`).
pub fn plan(
    input_dir: &Path,
    output_dir: &Path,
    extension: Option<&str>,
) -> Result<BatchPlan, CliError> {
    let exclude = std::fs::canonicalize(output_dir).ok();
    let mut plan = BatchPlan::default();
    let mut music = Vec::new();
    for path in files_under(input_dir, exclude.as_deref())? {
        let rel = path.strip_prefix(input_dir).unwrap_or(&path).to_path_buf();
        if is_music(&path) {
            music.push((path, rel));
        } else {
            plan.not_music.push(rel);
        }
    }
    let named = |rel: &Path, keep_extension: bool| {
        let base = if keep_extension {
            rel.file_name()
        } else {
            rel.file_stem()
        }
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
        let name = match extension {
            Some(ext) => format!("{base}.{ext}"),
            None => base,
        };
        output_dir
            .join(rel.parent().unwrap_or(Path::new("")))
            .join(name)
    };
    let short: Vec<PathBuf> = music.iter().map(|(_, rel)| named(rel, false)).collect();
    for (k, (path, rel)) in music.iter().enumerate() {
        let clash = short.iter().filter(|o| **o == short[k]).count() > 1;
        plan.items.push(BatchItem {
            input: path.clone(),
            output: if clash {
                named(rel, true)
            } else {
                short[k].clone()
            },
        });
    }
    Ok(plan)
}

/// A file that failed, and why.
#[derive(Debug, Clone, Serialize)]
pub struct BatchFailure {
    /// The input file.
    pub file: PathBuf,
    /// The error, one line.
    pub error: String,
}

/// `OUTDIR/batch_summary.json`.
#[derive(Debug, Serialize)]
pub struct BatchSummary {
    /// `generate` or `analyze`.
    pub command: String,
    /// The input folder.
    pub input_dir: PathBuf,
    /// The output folder.
    pub output_dir: PathBuf,
    /// Music files found.
    pub files: usize,
    /// Files processed and written.
    pub written: usize,
    /// Files left alone because their output existed (`--skip-existing`).
    pub skipped_existing: usize,
    /// Files that failed.
    pub failed: Vec<BatchFailure>,
    /// Files that are not music (by extension), not processed.
    pub not_music: Vec<PathBuf>,
    /// Files processed at once.
    pub jobs: usize,
    /// Wall-clock time of the batch.
    pub elapsed_s: f64,
}

/// Runs `process(input, output)` on every item of `plan` with `jobs` workers, one progress
/// bar, failures collected; writes the summary and returns an error when any file failed.
pub fn run_batch(
    command: &str,
    input_dir: &Path,
    output_dir: &Path,
    plan: BatchPlan,
    options: &BatchArgs,
    report: &Reporter,
    process: impl Fn(&Path, &Path) -> Result<(), CliError> + Sync,
) -> Result<(), CliError> {
    let t0 = Instant::now();
    std::fs::create_dir_all(output_dir).map_err(|e| CliError::Output {
        path: output_dir.to_path_buf(),
        reason: format!("cannot create the output folder ({e})"),
    })?;
    let jobs = options.jobs.map_or_else(
        || std::thread::available_parallelism().map_or(1, |n| n.get()),
        |n| n as usize,
    );
    let (todo, done): (Vec<&BatchItem>, Vec<&BatchItem>) = plan
        .items
        .iter()
        .partition(|item| !(options.skip_existing && item.output.exists()));
    let bar = report.progress(todo.len() as u64, &format!("{command} (files)"));
    let failures = Mutex::new(Vec::new());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| CliError::Usage(format!("--jobs {jobs}: cannot start the workers ({e})")))?;
    pool.install(|| {
        todo.par_iter().with_max_len(1).for_each(|item| {
            let made = item
                .output
                .parent()
                .map_or(Ok(()), std::fs::create_dir_all)
                .map_err(|e| CliError::Output {
                    path: item.output.clone(),
                    reason: format!("cannot create its folder ({e})"),
                })
                .and_then(|()| process(&item.input, &item.output));
            if let Err(e) = made {
                if let Ok(mut f) = failures.lock() {
                    f.push(BatchFailure {
                        file: item.input.clone(),
                        error: e.to_string(),
                    });
                }
            }
            bar.inc(1);
        });
    });
    bar.finish_and_clear();
    let mut failed = failures.into_inner().unwrap_or_default();
    failed.sort_by(|a, b| a.file.cmp(&b.file));
    let summary = BatchSummary {
        command: command.to_string(),
        input_dir: input_dir.to_path_buf(),
        output_dir: output_dir.to_path_buf(),
        files: plan.items.len(),
        written: todo.len() - failed.len(),
        skipped_existing: done.len(),
        failed,
        not_music: plan.not_music,
        jobs,
        elapsed_s: t0.elapsed().as_secs_f64(),
    };
    let summary_path = output_dir.join(SUMMARY_FILE);
    crate::output::write_atomically(&summary_path, |w| {
        serde_json::to_writer_pretty(w, &summary).map_err(|e| e.to_string())
    })?;
    report.line(&format!(
        "{}: {} music files → {} written, {} skipped (output exists), {} failed, {} not music, in {:.1} s with {jobs} jobs; summary in {}",
        input_dir.display(),
        summary.files,
        summary.written,
        summary.skipped_existing,
        summary.failed.len(),
        summary.not_music.len(),
        summary.elapsed_s,
        summary_path.display()
    ));
    for f in &summary.failed {
        eprintln!("failed: {}", f.error);
    }
    if summary.failed.is_empty() {
        Ok(())
    } else {
        Err(CliError::BatchFailed {
            failed: summary.failed.len(),
            files: todo.len(),
            summary: summary_path,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plan_mirrors_folders_and_disambiguates_clashing_stems() {
        let dir = tempfile::tempdir().unwrap();
        let inp = dir.path().join("in");
        std::fs::create_dir_all(inp.join("sub")).unwrap();
        for f in ["a.wav", "a.FLAC", "b.mid", "sub/c.ogg", "notes.txt"] {
            std::fs::write(inp.join(f), b"x").unwrap();
        }
        let out = dir.path().join("out");
        let p = plan(&inp, &out, Some("json")).unwrap();
        let outputs: Vec<PathBuf> = p.items.iter().map(|i| i.output.clone()).collect();
        assert_eq!(
            outputs,
            vec![
                out.join("a.FLAC.json"),
                out.join("a.wav.json"),
                out.join("b.json"),
                out.join("sub").join("c.json"),
            ]
        );
        assert_eq!(p.not_music, vec![PathBuf::from("notes.txt")]);
        // An output folder inside the input folder is not searched.
        let inner = inp.join("out");
        std::fs::create_dir_all(&inner).unwrap();
        std::fs::write(inner.join("old.wav"), b"x").unwrap();
        let p = plan(&inp, &inner, None).unwrap();
        assert_eq!(p.items.len(), 4);
        assert_eq!(p.items[2].output, inner.join("b"));
    }
}
