//! Reading the YTVF violin fingering dataset (feature `train`): 30 pieces, each one
//! professional performance whose fingering was annotated note by note from its video
//! (github.com/wayonbvc/Violin-Fingering-Generation-Through-Audio-Symbolic-Fusion, folder
//! `YTVF_dataset`). It states no licence, so it is read from a directory the user gives and
//! never shipped. None of its works is one of the TNUA pieces reserved for evaluation.
//!
//! Each `NAME.csv` has a header naming at least the columns `pitch`, `bars`, `start`,
//! `string` (1..=4 = G D A E), `position` and `finger` (0 = open); a row whose `harmonic`
//! column is not empty is a harmonic, whose sounding pitch no stopped place plays, and is
//! skipped.

use std::path::Path;

use crate::error::FingeringError;
use crate::train::{Label, Piece};

/// Reads every `*.csv` file of `dir` as one piece with one performer's labels (pieces
/// sorted by name, notes in file order, harmonics left out).
///
/// ```no_run
/// let pieces = fingering::ytvf::read_ytvf_dir(std::path::Path::new("YTVF_dataset"))?;
/// assert_eq!(pieces[0].labels[0].len(), 1); // one performer per piece
/// # Ok::<(), fingering::FingeringError>(())
/// ```
pub fn read_ytvf_dir(dir: &Path) -> Result<Vec<Piece>, FingeringError> {
    let listing = std::fs::read_dir(dir).map_err(|e| FingeringError::Dataset {
        path: dir.display().to_string(),
        reason: format!("cannot list ({e})"),
    })?;
    let mut paths: Vec<_> = listing
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "csv"))
        .collect();
    paths.sort();
    if paths.is_empty() {
        return Err(FingeringError::Dataset {
            path: dir.display().to_string(),
            reason: "no .csv files (give the YTVF_dataset folder)".into(),
        });
    }
    paths.iter().map(|p| read_piece(p)).collect()
}

/// One row of a YTVF file: a note with its timing in beats, its fingering and its bowing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct YtvfNote {
    /// MIDI pitch.
    pub midi: u8,
    /// The bar the note starts in, as numbered in the file.
    pub bar: i32,
    /// Onset within the bar, beats.
    pub start_beats: f64,
    /// Notated duration, beats.
    pub duration_beats: f64,
    /// String, position and finger.
    pub label: Label,
    /// 1 down-bow, 2 up-bow, 3 right-hand and 4 left-hand pizzicato, 0 not given.
    pub bowing: u8,
    /// A natural or artificial harmonic.
    pub harmonic: bool,
}

/// Reads one YTVF file's rows in file order (harmonics included, marked).
pub fn read_ytvf_notes(path: &Path) -> Result<Vec<YtvfNote>, FingeringError> {
    let err = |reason: String| FingeringError::Dataset {
        path: path.display().to_string(),
        reason,
    };
    let text = std::fs::read_to_string(path).map_err(|e| err(format!("cannot read ({e})")))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or_else(|| err("empty file".into()))?
        .split(',')
        .map(str::trim)
        .collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| err(format!("no `{name}` column in the header")))
    };
    let [pitch, bars, start, duration, string, position, finger] = [
        "pitch", "bars", "start", "duration", "string", "position", "finger",
    ]
    .map(&column);
    let (pitch, bars, start, duration) = (pitch?, bars?, start?, duration?);
    let (string, position, finger) = (string?, position?, finger?);
    let (bowing, harmonic) = (column("bowing").ok(), column("harmonic").ok());
    let mut out = Vec::new();
    for (i, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let bad = |k: usize, what: &str| {
            let name = header.get(k).copied().unwrap_or("?");
            err(format!("line {}: column `{name}` is not {what}", i + 2))
        };
        let number = |k: usize| -> Result<f64, FingeringError> {
            (fields.get(k).and_then(|v| v.parse::<f64>().ok()))
                .filter(|v| v.is_finite() && v.abs() < 1e6)
                .ok_or_else(|| bad(k, "a number"))
        };
        let small = |k: usize| -> Result<u8, FingeringError> {
            let v = number(k).map_err(|_| bad(k, "a whole number 0..=127"))?;
            if (0.0..=127.0).contains(&v) && v.fract() == 0.0 {
                Ok(v as u8)
            } else {
                Err(bad(k, "a whole number 0..=127"))
            }
        };
        let bow = match bowing.and_then(|k| fields.get(k)).filter(|v| !v.is_empty()) {
            Some(_) => bowing.map_or(Ok(0), small)?,
            None => 0,
        };
        out.push(YtvfNote {
            midi: small(pitch)?,
            bar: number(bars)? as i32,
            start_beats: number(start)?,
            duration_beats: number(duration)?,
            label: Label {
                string: small(string)?,
                position: small(position)?,
                finger: small(finger)?,
            },
            bowing: bow,
            harmonic: harmonic.is_some_and(|k| fields.get(k).is_some_and(|v| !v.is_empty())),
        });
    }
    Ok(out)
}

fn read_piece(path: &Path) -> Result<Piece, FingeringError> {
    let sequence: Vec<(u8, Label)> = read_ytvf_notes(path)?
        .iter()
        .filter(|n| !n.harmonic)
        .map(|n| (n.midi, n.label))
        .collect();
    let name = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().to_string());
    Ok(Piece {
        name,
        midi: sequence.iter().map(|s| s.0).collect(),
        labels: sequence
            .iter()
            .map(|s| vec![Some(s.1).filter(|l| l.string != 0)])
            .collect(),
        sequences: vec![sequence],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir_with(name: &str, files: &[(&str, &str)]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("ytvf-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        for (file, text) in files {
            std::fs::write(dir.join(file), text).unwrap();
        }
        dir
    }

    const HEADER: &str = "pitch,bars,start,duration,string,position,finger,bowing,harmonic\n";

    #[test]
    fn reads_a_piece_and_skips_harmonics() {
        let text = format!("{HEADER}62,1,0,1,2,1,0,1,\n88,1,1,1,4,3,4,2,1\n64,1,2,1,2,1,1,1,\n");
        let dir = dir_with("ok", &[("B tune.csv", &text), ("A tune.csv", &text)]);
        let pieces = read_ytvf_dir(&dir).unwrap();
        assert_eq!(pieces.len(), 2);
        assert_eq!(pieces[0].name, "A tune");
        assert_eq!(pieces[0].midi, vec![62, 64]);
        assert_eq!(
            pieces[0].labels[1],
            vec![Some(Label {
                string: 2,
                position: 1,
                finger: 1
            })]
        );
        assert_eq!(pieces[0].sequences.len(), 1);
        let notes = read_ytvf_notes(&dir.join("A tune.csv")).unwrap();
        assert_eq!(notes.len(), 3);
        assert!(notes[1].harmonic && !notes[2].harmonic);
        assert_eq!(notes[1].bowing, 2);
        let last = notes[2];
        assert_eq!(
            (last.bar, last.start_beats, last.duration_beats, last.bowing),
            (1, 2.0, 1.0, 1)
        );
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn refuses_bad_files_with_the_reason() {
        let missing = dir_with(
            "missing",
            &[(
                "x.csv",
                "pitch,bars,start,duration,string,position\n62,1,0,1,2,1\n",
            )],
        );
        let e = read_ytvf_dir(&missing).unwrap_err().to_string();
        assert!(e.contains("no `finger` column"), "{e}");
        let bad = dir_with(
            "bad",
            &[("x.csv", &format!("{HEADER}62,1,0,1,2,1.5,0,1,\n"))],
        );
        let e = read_ytvf_dir(&bad).unwrap_err().to_string();
        assert!(e.contains("line 2") && e.contains("position"), "{e}");
        let nan = dir_with(
            "nan",
            &[("x.csv", &format!("{HEADER}NaN,1,0,1,2,1,0,1,\n"))],
        );
        let e = read_ytvf_dir(&nan).unwrap_err().to_string();
        assert!(e.contains("`pitch`"), "{e}");
        let cut = dir_with("cut", &[("x.csv", &format!("{HEADER}62,1,0,1,2\n"))]);
        let e = read_ytvf_dir(&cut).unwrap_err().to_string();
        assert!(e.contains("`position`"), "{e}");
        let empty = dir_with("empty", &[]);
        assert!(read_ytvf_dir(&empty).is_err());
        for d in [missing, bad, nan, cut, empty] {
            let _ = std::fs::remove_dir_all(d);
        }
    }
}
