//! Repertoire: scores exported from public-domain collections by
//! `scripts/export_repertoire.py` (one JSON file per part), read into [`Score`]s.
//!
//! A file that cannot be read or fails a check is skipped and reported with its reason
//! (the corpus manifest lists it); it never aborts a build. Reserved works (see
//! `DATA_SOURCES.md`) are refused here too, whatever their file says.

use std::path::{Path, PathBuf};

use performance::TimeSignature;
use serde::{Deserialize, Serialize};

use crate::error::CorpusError;
use crate::score::{Bar, PartNote, Provenance, Score};

/// The `schema` field this reader understands.
pub const SCORE_SCHEMA: &str = "violin-skeleton-score/1";

/// Works that are never used by the corpus in any form (held back for the product's
/// evaluation on music it has never seen). Matched case-insensitively against id and title.
pub const RESERVED_PATTERNS: [&str; 7] = [
    "mozart/k458",
    "haydn/opus74no1",
    "beethoven/opus18no1",
    "bach/",
    "bwv 100",
    "wohlfahrt",
    "kayser",
];

/// Whether `text` names a reserved work.
///
/// ```
/// assert!(corpus::repertoire::is_reserved("mozart/k458/movement1/violin1"));
/// assert!(!corpus::repertoire::is_reserved("mozart/k80/movement1/violin1"));
/// ```
pub fn is_reserved(text: &str) -> bool {
    let t = text.to_lowercase().replace("bwv100", "bwv 100");
    RESERVED_PATTERNS.iter().any(|p| t.contains(p))
}

#[derive(Deserialize)]
struct FileBar {
    start_q: f64,
    len_q: f64,
    numerator: u8,
    denominator: u8,
}

#[derive(Deserialize)]
struct FileNote {
    start_q: f64,
    dur_q: f64,
    midi: Vec<i64>,
    #[serde(default)]
    slurred: bool,
    #[serde(default)]
    staccato: bool,
    #[serde(default)]
    accent: bool,
    #[serde(default)]
    fermata: bool,
    #[serde(default)]
    dynamic: Option<f32>,
}

#[derive(Deserialize)]
struct ScoreFile {
    schema: String,
    id: String,
    work: String,
    #[serde(default)]
    collection: String,
    #[serde(default)]
    title: String,
    #[serde(default)]
    source: String,
    #[serde(default)]
    license: String,
    #[serde(default)]
    tempo_qpm: Option<f64>,
    bars: Vec<FileBar>,
    notes: Vec<FileNote>,
}

/// A score file that was not used, and why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SkippedScore {
    /// The file.
    pub file: PathBuf,
    /// Why it was skipped.
    pub reason: String,
}

/// Reads one score file.
pub fn read_score(path: &Path) -> Result<Score, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read ({e})"))?;
    let file: ScoreFile =
        serde_json::from_str(&text).map_err(|e| format!("not a score file ({e})"))?;
    if file.schema != SCORE_SCHEMA {
        return Err(format!(
            "schema {:?}, expected {SCORE_SCHEMA:?}",
            file.schema
        ));
    }
    if is_reserved(&file.id) || is_reserved(&file.work) || is_reserved(&file.title) {
        return Err("reserved work (never used by the corpus)".into());
    }
    let mut bars = Vec::with_capacity(file.bars.len());
    for b in &file.bars {
        let ts = TimeSignature::new(b.numerator, b.denominator);
        if !(ts.is_valid() && b.start_q.is_finite() && b.len_q.is_finite() && b.len_q > 0.0) {
            return Err(format!("bad bar at {} quarters", b.start_q));
        }
        bars.push(Bar {
            start_q: b.start_q,
            len_q: b.len_q,
            time_signature: ts,
        });
    }
    if bars.windows(2).any(|w| w[1].start_q < w[0].start_q) {
        return Err("bars out of order".into());
    }
    let mut notes: Vec<PartNote> = Vec::with_capacity(file.notes.len());
    for n in &file.notes {
        let mut pitches: Vec<u8> = n
            .midi
            .iter()
            .filter_map(|&m| u8::try_from(m).ok())
            .filter(|m| (55..=100).contains(m))
            .collect();
        pitches.sort_unstable_by(|a, b| b.cmp(a));
        let Some((&top, lower)) = pitches.split_first() else {
            continue;
        };
        if !(n.start_q.is_finite() && n.dur_q.is_finite() && n.dur_q > 0.0 && n.start_q >= 0.0) {
            return Err(format!("bad note timing at {} quarters", n.start_q));
        }
        let dynamic = n
            .dynamic
            .filter(|d| d.is_finite())
            .map(|d| d.clamp(0.0, 1.0));
        let note = PartNote {
            start_q: n.start_q,
            dur_q: n.dur_q,
            midi: top,
            lower: lower.to_vec(),
            slurred_from_previous: n.slurred,
            dynamic,
            accent: n.accent,
            staccato: n.staccato,
            fermata: n.fermata,
        };
        // One voice: at a shared onset the higher note wins; an earlier note is cut where
        // the next one starts.
        match notes.last_mut() {
            Some(prev) if (prev.start_q - note.start_q).abs() < 1e-6 => {
                if note.midi > prev.midi {
                    *prev = note;
                }
            }
            Some(prev) if note.start_q < prev.start_q => {
                return Err("notes out of order".into());
            }
            Some(prev) => {
                prev.dur_q = prev.dur_q.min(note.start_q - prev.start_q);
                notes.push(note);
            }
            None => notes.push(note),
        }
    }
    if notes.len() < 8 {
        return Err(format!("only {} playable notes", notes.len()));
    }
    if bars.is_empty() {
        return Err("no bars".into());
    }
    if let Some(n) = notes.first_mut() {
        n.slurred_from_previous = false;
    }
    let ts = bars
        .iter()
        .find(|b| !b.is_partial())
        .unwrap_or(&bars[0])
        .time_signature;
    let tempo_bpm = file
        .tempo_qpm
        .filter(|t| t.is_finite() && *t > 0.0)
        .map(|t| t / ts.beat_quarters());
    Ok(Score {
        work: file.work,
        id: file.id,
        bars,
        notes,
        tempo_bpm,
        provenance: Provenance {
            collection: file.collection,
            title: file.title,
            source: file.source,
            license: file.license,
        },
    })
}

/// Reads every `*.json` score below `dir` (sorted by file name, so the order is stable),
/// returning the scores and the files skipped with their reasons.
pub fn read_dir(dir: &Path) -> Result<(Vec<Score>, Vec<SkippedScore>), CorpusError> {
    let entries = std::fs::read_dir(dir).map_err(|e| CorpusError::Io {
        path: dir.to_path_buf(),
        reason: format!("cannot read the repertoire folder ({e})"),
    })?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    let (mut scores, mut skipped) = (Vec::new(), Vec::new());
    for f in files {
        match read_score(&f) {
            Ok(s) => scores.push(s),
            Err(reason) => skipped.push(SkippedScore { file: f, reason }),
        }
    }
    if scores.is_empty() {
        return Err(CorpusError::Config(format!(
            "{}: no usable score (run scripts/export_repertoire.py --out {} first){}",
            dir.display(),
            dir.display(),
            skipped
                .first()
                .map(|s| format!("; e.g. {}: {}", s.file.display(), s.reason))
                .unwrap_or_default()
        )));
    }
    Ok((scores, skipped))
}
