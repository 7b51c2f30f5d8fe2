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

/// The progress line of a training epoch (`epoch` counted from 0 of `epochs`): the mean loss
/// and, once a validation has run, its `measure` (e.g. `F1`, `r`) and the best so far as
/// `(last, best)`. Before the first validation both read "–": a 0.000 there would look like
/// a result.
pub fn epoch_line(
    (epoch, epochs): (usize, usize),
    elapsed_s: f64,
    loss: f32,
    measure: &str,
    validated: Option<(f64, f64)>,
) -> String {
    let (last, best) = match validated {
        Some((last, best)) => (format!("{last:.3}"), format!("{best:.3}")),
        None => ("–".to_string(), "–".to_string()),
    };
    format!(
        "epoch {}/{epochs} ({elapsed_s:.0} s) loss {loss:.4} val {measure} {last} (best {best})",
        epoch + 1
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_score_is_shown_before_the_first_validation() {
        let first = epoch_line((0, 12), 3.4, 0.25, "F1", None);
        assert_eq!(first, "epoch 1/12 (3 s) loss 0.2500 val F1 – (best –)");
        assert!(!first.contains("0.000"));
        let later = epoch_line((1, 12), 60.0, 0.2, "r", Some((0.71, 0.74)));
        assert_eq!(
            later,
            "epoch 2/12 (60 s) loss 0.2000 val r 0.710 (best 0.740)"
        );
    }
}
