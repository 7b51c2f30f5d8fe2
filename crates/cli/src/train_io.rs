//! What the `train` commands share: progress bars, the data folder's name, JSON reports.

use std::path::Path;

use crate::error::CliError;
use crate::Reporter;

/// A loading bar fed by a library's `(done, total)` callback.
pub fn loading_bar(report: &Reporter, what: &str) -> indicatif::ProgressBar {
    report.progress(0, what)
}

/// The data folder as recorded in the weights file.
pub fn describe(dir: &Path) -> String {
    dir.file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("data")
        .to_string()
}

/// Writes a JSON report atomically.
pub fn write_json<T: serde::Serialize>(path: &Path, value: &T) -> Result<(), CliError> {
    let text = serde_json::to_string_pretty(value).map_err(|e| CliError::Output {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    crate::output::write_atomically(path, |w| {
        w.write_all(text.as_bytes()).map_err(|e| e.to_string())
    })
}
