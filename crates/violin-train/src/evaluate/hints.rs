//! Beat hints from a corpus item's labels, to measure what a user who knows the time
//! signature or the tempo gets (`violin-skeleton evaluate --hints`).

use std::path::Path;

use performance::TimeSignature;
use violin_skeleton::{hint_tempo_range_around, BeatHints};

use super::datasets::{LabelSource, LabelledRecording};

/// Which labels become hints.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LabelHints {
    /// None: the blind analysis.
    #[default]
    None,
    /// The written time signature.
    TimeSignature,
    /// The nominal tempo, ±15 % ([`violin_skeleton::HINT_SINGLE_TEMPO_TOLERANCE`]).
    Tempo,
    /// Both.
    Both,
}

impl LabelledRecording {
    /// The corpus item folder (`None` for a URMP track).
    pub fn corpus_item_dir(&self) -> Option<&Path> {
        match &self.labels {
            LabelSource::Corpus { dir, .. } => Some(dir),
            LabelSource::Urmp { .. } => None,
        }
    }
}

/// The hints `which` asks for, from the `labels.json` in `item_dir` (`time_signature` as
/// "N/D", `tempo_bpm` at the notated beat); a label that is missing or unreadable gives no
/// hint.
pub fn hints_from_labels(item_dir: &Path, which: LabelHints) -> BeatHints {
    if which == LabelHints::None {
        return BeatHints::default();
    }
    let labels: Option<serde_json::Value> = std::fs::read_to_string(item_dir.join("labels.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let time_signature = labels.as_ref().and_then(|l| {
        l.get("time_signature")?
            .as_str()?
            .parse::<TimeSignature>()
            .ok()
    });
    let tempo = labels
        .as_ref()
        .and_then(|l| l.get("tempo_bpm")?.as_f64())
        .filter(|t| t.is_finite() && *t > 0.0)
        .map(hint_tempo_range_around);
    BeatHints {
        time_signature: time_signature
            .filter(|_| matches!(which, LabelHints::TimeSignature | LabelHints::Both)),
        tempo_range_bpm: tempo.filter(|_| matches!(which, LabelHints::Tempo | LabelHints::Both)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hints_come_from_the_labels_asked_for() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(
            hints_from_labels(dir.path(), LabelHints::Both),
            BeatHints::default()
        );
        std::fs::write(
            dir.path().join("labels.json"),
            r#"{"time_signature": "6/8", "tempo_bpm": 100.0}"#,
        )
        .unwrap();
        let both = hints_from_labels(dir.path(), LabelHints::Both);
        assert_eq!(both.time_signature, Some(TimeSignature::new(6, 8)));
        let (lo, hi) = both.tempo_range_bpm.unwrap();
        assert!((lo * 1.15 - 100.0).abs() < 1e-9 && (hi - 115.0).abs() < 1e-9);
        let ts = hints_from_labels(dir.path(), LabelHints::TimeSignature);
        assert!(ts.time_signature.is_some() && ts.tempo_range_bpm.is_none());
        let tempo = hints_from_labels(dir.path(), LabelHints::Tempo);
        assert!(tempo.time_signature.is_none() && tempo.tempo_range_bpm.is_some());
        assert!(hints_from_labels(dir.path(), LabelHints::None).is_empty());
    }
}
