//! The labelled folders `evaluate` reads: a corpus (`manifest.json` + `items/NNNNN/`) or a
//! URMP layout (`AuSep_K_vn_NAME.wav` with `openpose_K_vn_NAME/` beside it, and URMP's
//! `F0s_K_vn_NAME.txt` / `Notes_K_vn_NAME.txt` when present).

use std::path::{Path, PathBuf};

use corpus::manifest::{Manifest, Split};
use skeleton::{formats::MotionFormat, Motion};

use crate::error::{Result, TrainError};

/// Which layout a folder has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// `violin-skeleton corpus` output.
    Corpus,
    /// URMP-style violin tracks with OpenPose folders.
    Urmp,
}

impl Layout {
    /// `corpus` or `urmp`.
    pub fn name(self) -> &'static str {
        match self {
            Layout::Corpus => "corpus",
            Layout::Urmp => "urmp",
        }
    }
}

/// Which part of a dataset to evaluate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SplitChoice {
    /// The held-out test split (default).
    #[default]
    Test,
    /// The validation split.
    Val,
    /// The training split.
    Train,
    /// Everything.
    All,
}

impl SplitChoice {
    /// `test`, `val`, `train` or `all`.
    pub fn name(self) -> &'static str {
        match self {
            SplitChoice::Test => "test",
            SplitChoice::Val => "val",
            SplitChoice::Train => "train",
            SplitChoice::All => "all",
        }
    }

    fn admits(self, split: Split) -> bool {
        matches!(
            (self, split),
            (SplitChoice::All, _)
                | (SplitChoice::Test, Split::Test)
                | (SplitChoice::Val, Split::Val)
                | (SplitChoice::Train, Split::Train)
        )
    }
}

/// Where one recording's labels are.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum LabelSource {
    Corpus { dir: PathBuf, tuning_cents: f64 },
    Urmp { openpose: PathBuf },
}

/// A recording with its labels on disk.
#[derive(Debug, Clone, PartialEq)]
pub struct LabelledRecording {
    /// Item folder or track file name.
    pub name: String,
    /// Evaluation set of a many-violin corpus (`corpus::manifest::ManifestItem::
    /// evaluation_set`), the renderer (`builtin`, `soundfont`) of an older corpus, or `urmp`.
    pub group: String,
    /// The audio file.
    pub audio: PathBuf,
    pub(super) labels: LabelSource,
}

/// A frame-time → reference f0 function: `Some(hz)` (0 unvoiced) or `None` where the labels
/// cannot decide and the frame is not scored.
pub type F0Reference = Box<dyn Fn(f64) -> Option<f32> + Send + Sync>;

/// The references a recording has (`None` where the dataset has none).
pub struct References {
    /// Bow changes in seconds.
    pub bow_changes_s: Option<Vec<f64>>,
    /// Reference f0 at any time.
    pub f0_hz_at: Option<F0Reference>,
    /// Note onsets in seconds.
    pub onsets_s: Option<Vec<f64>>,
    /// Beats in seconds.
    pub beats_s: Option<Vec<f64>>,
    /// Downbeats in seconds.
    pub downbeats_s: Option<Vec<f64>>,
    /// Labelled strokes and the strings of the sounding notes (corpus only).
    pub bowing: Option<super::StrokeReferences>,
    /// Beats per bar and tempo (bpm) at the notated beat (`labels.json`).
    pub notated_meter: (Option<u8>, Option<f64>),
    /// The reference skeleton.
    pub motion: Option<Motion>,
    /// Whether the reference skeleton is in our camera's image space (pixel L1 is
    /// meaningful).
    pub same_image_space: bool,
}

fn data_err(path: &Path, reason: impl std::fmt::Display) -> TrainError {
    TrainError::Dataset {
        path: path.to_path_buf(),
        reason: reason.to_string(),
    }
}

fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path).map_err(|e| data_err(path, format!("cannot read ({e})")))
}

/// Rows of numbers (whitespace, tab or comma separated); lines that do not start with a
/// number (headers) are skipped.
fn read_rows(path: &Path) -> Result<Vec<Vec<f64>>> {
    let text = read_text(path)?;
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let Some(first) = fields.first() else {
            continue;
        };
        if first.parse::<f64>().is_err() {
            continue;
        }
        let mut row = Vec::with_capacity(fields.len());
        for f in fields {
            let v: f64 = f
                .parse()
                .map_err(|_| data_err(path, format!("line {}: \"{f}\" is not a number", i + 1)))?;
            if !v.is_finite() {
                return Err(data_err(path, format!("line {}: {v} is not finite", i + 1)));
            }
            row.push(v);
        }
        rows.push(row);
    }
    Ok(rows)
}

fn first_column(path: &Path) -> Result<Vec<f64>> {
    Ok(read_rows(path)?.into_iter().map(|r| r[0]).collect())
}

/// Frames this close to a labelled note onset or offset are not scored (attacks, releases and
/// slur glides of about 25 ms).
const EDGE_S: f64 = 0.03;
/// Nor is the release and reverb tail after a note that no other note follows this soon
/// (the corpus does not label it).
const TAIL_S: f64 = 0.2;

/// The reference f0 of labelled notes `(onset_s, offset_s, hz)`: the note's pitch inside it,
/// unvoiced between notes, `None` near note edges and in release tails (see [`EDGE_S`],
/// [`TAIL_S`]; the same rule as `scripts/compare_analysis_librosa.py`).
fn f0_from_segments(mut segments: Vec<(f64, f64, f32)>) -> F0Reference {
    segments.sort_by(|a, b| a.0.total_cmp(&b.0));
    Box::new(move |t: f64| {
        let k = segments.partition_point(|s| s.0 <= t + EDGE_S);
        let near = &segments[k.saturating_sub(4)..(k + 1).min(segments.len())];
        if near
            .iter()
            .any(|&(on, off, _)| (t - on).abs() < EDGE_S || (t - off).abs() < EDGE_S)
        {
            return None;
        }
        if let Some(&(_, _, hz)) = near
            .iter()
            .find(|&&(on, off, _)| t >= on + EDGE_S && t < off - EDGE_S)
        {
            return Some(hz);
        }
        let sounding = near
            .iter()
            .any(|&(on, off, _)| t >= on - EDGE_S && t < off + EDGE_S);
        let in_tail = near.iter().any(|&(_, off, _)| t >= off && t < off + TAIL_S);
        if in_tail && !sounding {
            None
        } else {
            Some(0.0)
        }
    })
}

/// A URMP `F0s_*.txt` track (`time_s f0_hz` per line), looked up at the nearest time.
fn f0_from_track(rows: Vec<Vec<f64>>, path: &Path) -> Result<F0Reference> {
    let mut points: Vec<(f64, f32)> = Vec::with_capacity(rows.len());
    for r in rows {
        if r.len() < 2 {
            return Err(data_err(path, "expected two columns: time_s and f0_hz"));
        }
        points.push((r[0], r[1] as f32));
    }
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(Box::new(move |t: f64| {
        let i = points.partition_point(|p| p.0 < t);
        let candidates = [i.checked_sub(1), Some(i)];
        candidates
            .iter()
            .flatten()
            .filter_map(|&k| points.get(k))
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
            .map(|p| p.1)
    }))
}

impl LabelledRecording {
    /// Reads the recording's labels.
    pub fn references(&self) -> Result<References> {
        match &self.labels {
            LabelSource::Corpus { dir, tuning_cents } => {
                let notes_path = dir.join("notes.tsv");
                let notes = read_rows(&notes_path)?;
                let mut segments = Vec::with_capacity(notes.len());
                for n in &notes {
                    if n.len() < 3 {
                        return Err(data_err(&notes_path, "expected onset_s, offset_s, midi"));
                    }
                    let hz = pitch_track::midi_to_hz((n[2] + tuning_cents / 100.0) as f32);
                    segments.push((n[0], n[1], hz));
                }
                let motion_path = dir.join("motion.json");
                Ok(References {
                    bowing: Some(super::StrokeReferences::read(dir, &notes)?),
                    notated_meter: crate::beat_data::notated_meter(dir),
                    bow_changes_s: Some(first_column(&dir.join("bowchanges.txt"))?),
                    onsets_s: Some(notes.iter().map(|n| n[0]).collect()),
                    f0_hz_at: Some(f0_from_segments(segments)),
                    beats_s: Some(first_column(&dir.join("beats.txt"))?),
                    downbeats_s: Some(first_column(&dir.join("downbeats.txt"))?),
                    motion: Some(
                        Motion::read(&motion_path, MotionFormat::Json)
                            .map_err(|e| data_err(&motion_path, e))?,
                    ),
                    same_image_space: true,
                })
            }
            LabelSource::Urmp { openpose } => {
                let pose = pose_preproc::preprocess_dir(openpose, &Default::default())
                    .map_err(|e| data_err(openpose, e))?;
                let fps = pose.motion.fps();
                let stem = urmp_stem(&self.audio).unwrap_or_default();
                let dir = self.audio.parent().unwrap_or(Path::new("."));
                let f0_path = dir.join(format!("F0s_{stem}.txt"));
                let notes_path = dir.join(format!("Notes_{stem}.txt"));
                let f0_hz_at = if f0_path.is_file() {
                    Some(f0_from_track(read_rows(&f0_path)?, &f0_path)?)
                } else {
                    None
                };
                let onsets_s = if notes_path.is_file() {
                    Some(first_column(&notes_path)?)
                } else {
                    None
                };
                Ok(References {
                    bow_changes_s: Some(
                        pose.bow_change_frames
                            .iter()
                            .map(|&f| f as f64 / fps)
                            .collect(),
                    ),
                    f0_hz_at,
                    onsets_s,
                    beats_s: None,
                    downbeats_s: None,
                    bowing: None,
                    notated_meter: (None, None),
                    motion: Some(pose.motion),
                    same_image_space: false,
                })
            }
        }
    }
}

/// `K_vn_NAME` of `AuSep_K_vn_NAME.wav`.
fn urmp_stem(audio: &Path) -> Option<String> {
    let name = audio.file_name()?.to_str()?;
    let stem = name.strip_prefix("AuSep_")?.strip_suffix(".wav")?;
    (stem.split('_').nth(1) == Some("vn")).then(|| stem.to_string())
}

fn find_urmp(dir: &Path, out: &mut Vec<(PathBuf, PathBuf)>) -> Result<()> {
    let entries =
        std::fs::read_dir(dir).map_err(|e| data_err(dir, format!("cannot list ({e})")))?;
    for entry in entries {
        let path = entry.map_err(|e| data_err(dir, e))?.path();
        if path.is_dir() {
            find_urmp(&path, out)?;
        } else if let Some(stem) = urmp_stem(&path) {
            let openpose = dir.join(format!("openpose_{stem}"));
            if !openpose.is_dir() {
                return Err(data_err(
                    &path,
                    format!(
                        "no OpenPose folder for this track: expected {}",
                        openpose.display()
                    ),
                ));
            }
            out.push((path, openpose));
        }
    }
    Ok(())
}

/// The recordings of `dir` in `split`, in a stable order.
pub fn find_recordings(dir: &Path, split: SplitChoice) -> Result<(Layout, Vec<LabelledRecording>)> {
    if !dir.is_dir() {
        return Err(data_err(
            dir,
            "not a folder; give a corpus or URMP-layout folder",
        ));
    }
    let manifest_path = dir.join("manifest.json");
    if manifest_path.is_file() {
        let manifest: Manifest = serde_json::from_str(&read_text(&manifest_path)?)
            .map_err(|e| data_err(&manifest_path, format!("not a corpus manifest ({e})")))?;
        let recordings: Vec<LabelledRecording> = manifest
            .items
            .iter()
            .filter(|it| split.admits(it.split))
            .map(|it| {
                let item_dir = dir.join(&it.dir);
                LabelledRecording {
                    name: it.dir.clone(),
                    // Many-violin corpora report each evaluation set side by side;
                    // older corpora report per renderer.
                    group: if manifest.renderer == "many" {
                        it.evaluation_set().into()
                    } else {
                        it.renderer.name().into()
                    },
                    audio: item_dir.join(&it.audio),
                    labels: LabelSource::Corpus {
                        dir: item_dir,
                        tuning_cents: it.augmentation.tuning_cents,
                    },
                }
            })
            .collect();
        if recordings.is_empty() {
            return Err(data_err(
                &manifest_path,
                format!("no items in the {} split", split.name()),
            ));
        }
        return Ok((Layout::Corpus, recordings));
    }
    let mut tracks = Vec::new();
    find_urmp(dir, &mut tracks)?;
    tracks.sort();
    if tracks.is_empty() {
        return Err(data_err(
            dir,
            "neither a corpus (manifest.json) nor a URMP folder (AuSep_K_vn_NAME.wav + openpose_K_vn_NAME/)",
        ));
    }
    let splits = Split::assign(tracks.len());
    let recordings = tracks
        .into_iter()
        .zip(splits)
        .filter(|(_, s)| split.admits(*s))
        .map(|((audio, openpose), _)| LabelledRecording {
            name: audio
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().to_string()),
            group: "urmp".into(),
            audio,
            labels: LabelSource::Urmp { openpose },
        })
        .collect();
    Ok((Layout::Urmp, recordings))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_skip_headers_and_reject_garbage() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("notes.tsv");
        std::fs::write(&p, "onset_s\toffset_s\tmidi\n0.5\t1.0\t69\n\n1.0,2.0,71\n").unwrap();
        assert_eq!(
            read_rows(&p).unwrap(),
            vec![vec![0.5, 1.0, 69.0], vec![1.0, 2.0, 71.0]]
        );
        std::fs::write(&p, "0.5\tNaN\t69\n").unwrap();
        assert!(read_rows(&p).is_err());
        std::fs::write(&p, "0.5\tabc\t69\n").unwrap();
        assert!(matches!(read_rows(&p), Err(TrainError::Dataset { .. })));
    }

    #[test]
    fn reference_f0_follows_the_notes() {
        let f0 = f0_from_segments(vec![(1.0, 2.0, 440.0), (0.0, 0.5, 220.0)]);
        assert_eq!(f0(0.25), Some(220.0));
        assert_eq!(f0(0.51), None, "note edge");
        assert_eq!(f0(0.6), None, "release tail");
        assert_eq!(f0(0.75), Some(0.0), "a rest");
        assert_eq!(f0(1.5), Some(440.0));
        assert_eq!(f0(2.0), None);
        assert_eq!(f0(2.5), Some(0.0));
        let track = f0_from_track(
            vec![vec![0.0, 100.0], vec![0.01, 0.0], vec![0.02, 200.0]],
            Path::new("x"),
        )
        .unwrap();
        assert_eq!(track(0.004), Some(100.0));
        assert_eq!(track(0.017), Some(200.0));
    }

    #[test]
    fn urmp_names() {
        assert_eq!(
            urmp_stem(Path::new("a/AuSep_2_vn_03_Dance.wav")).as_deref(),
            Some("2_vn_03_Dance")
        );
        assert_eq!(urmp_stem(Path::new("a/AuSep_2_fl_03_Dance.wav")), None);
    }

    #[test]
    fn folders_that_are_neither_layout_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        assert!(find_recordings(dir.path(), SplitChoice::All).is_err());
        assert!(find_recordings(&dir.path().join("missing"), SplitChoice::All).is_err());
        std::fs::write(dir.path().join("manifest.json"), "{not json").unwrap();
        assert!(matches!(
            find_recordings(dir.path(), SplitChoice::All),
            Err(TrainError::Dataset { .. })
        ));
    }
}
