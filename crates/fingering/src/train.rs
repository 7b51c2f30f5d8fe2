//! Training and evaluation on the TNUA violin fingering dataset (feature `train`; not in the
//! default build). The dataset (Chen et al., IUI 2021,
//! github.com/Tsung-Ping/Violin-Fingering-Generation) states no licence, so it is not in
//! the repository: these functions read it from a directory the user gives.
//!
//! Layout: `vio{1..10}_{piece}.csv` with a header and columns `pitch, start (beats),
//! duration, beat_type, string, position, finger`; string 1..=4 = G D A E (0 = not
//! given), position 1..=12, finger 0 = open string.

use std::collections::BTreeMap;
use std::path::Path;

use crate::error::FingeringError;
use crate::fingering::Fingering;
use crate::learned::{context, interval_class, steps};
use crate::learned_params::LearnedParams;
use crate::placement::Placement;
use crate::span::{span_class, SpanContext};
use crate::string::ViolinString;

/// The pieces reserved for the final evaluation (issue #22): never read for training,
/// tuning or leave-one-piece-out.
pub const RESERVED_PIECES: [&str; 4] = ["bach1", "bach2", "flower", "mend1"];

/// One violinist's label of a note: string (1..=4, 0 = none), position, finger.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Label {
    /// 1..=4 = G D A E; 0 = not given.
    pub string: u8,
    /// Position as the violinist numbered it.
    pub position: u8,
    /// 0 = open string.
    pub finger: u8,
}

impl Label {
    /// The label as a place that plays `midi` (the placement that makes the pitch
    /// right), or `None` when no low/normal/high finger of that position plays it.
    pub fn to_fingering(self, midi: u8) -> Option<Fingering> {
        let string = ViolinString::from_number(self.string)?;
        if self.finger == 0 {
            return (midi == string.open_midi()).then(|| Fingering::open(string, self.position));
        }
        [Placement::Normal, Placement::Low, Placement::High]
            .into_iter()
            .map(|p| Fingering::with_placement(string, self.position, self.finger.min(4), p))
            .find(|f| f.midi() == midi && self.finger <= 4)
    }

    /// Whether a planned place agrees with this label on the string.
    pub fn same_string(&self, f: &Fingering) -> bool {
        self.string == f.string.number()
    }

    /// Whether a planned place agrees on string and position; an open string on both sides
    /// counts as a match on the string alone (an open string has no position of its own).
    pub fn same_string_position(&self, f: &Fingering) -> bool {
        self.same_string(f) && (self.position == f.position || (self.finger == 0 && f.is_open()))
    }
}

/// One piece: the note sequence (MIDI pitches in the most common version's order) and,
/// per note, each violinist's label (`None` where that violinist's file lacks the note or
/// gives no string).
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    /// The piece's name (`bach1`, `mend2`, …).
    pub name: String,
    /// MIDI pitch per note.
    pub midi: Vec<u8>,
    /// `labels[note][violinist]`.
    pub labels: Vec<Vec<Option<Label>>>,
    /// Each violinist's own sequence (pitch, label) in file order, for counting.
    pub sequences: Vec<Vec<(u8, Label)>>,
}

type Row = (i64, u8, Label); // (start in 1/1000 beat, pitch, label)

fn read_csv(path: &Path) -> Result<Vec<Row>, FingeringError> {
    let err = |reason: String| FingeringError::Dataset {
        path: path.display().to_string(),
        reason,
    };
    let text = std::fs::read_to_string(path).map_err(|e| err(format!("cannot read ({e})")))?;
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        let f: Vec<&str> = line.trim().split(',').collect();
        if f.len() < 7 {
            if line.trim().is_empty() {
                continue;
            }
            return Err(err(format!("line {}: expected 7 columns", i + 1)));
        }
        let num = |k: usize| -> Result<f64, FingeringError> {
            f[k].trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && v.abs() < 1e6)
                .ok_or_else(|| err(format!("line {}: column {} is not a number", i + 1, k + 1)))
        };
        let small = |k: usize| -> Result<u8, FingeringError> {
            let v = num(k)?;
            if (0.0..=127.0).contains(&v) {
                Ok(v as u8)
            } else {
                Err(err(format!(
                    "line {}: column {} out of range",
                    i + 1,
                    k + 1
                )))
            }
        };
        let label = Label {
            string: small(4)?,
            position: small(5)?,
            finger: small(6)?,
        };
        rows.push(((num(1)? * 1000.0).round() as i64, small(0)?, label));
    }
    Ok(rows)
}

/// Reads every piece of the dataset in `dir` (files `vio{N}_{piece}.csv`), pieces sorted by
/// name, violinists by number.
pub fn read_tnua_dir(dir: &Path) -> Result<Vec<Piece>, FingeringError> {
    let entries = std::fs::read_dir(dir).map_err(|e| FingeringError::Dataset {
        path: dir.display().to_string(),
        reason: format!("cannot list ({e})"),
    })?;
    let mut files: BTreeMap<String, BTreeMap<u32, Vec<Row>>> = BTreeMap::new();
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        let Some(stem) = name.strip_suffix(".csv") else {
            continue;
        };
        let Some((vio, piece)) = stem.split_once('_') else {
            continue;
        };
        let Some(Ok(n)) = vio.strip_prefix("vio").map(str::parse::<u32>) else {
            continue;
        };
        let rows = read_csv(&entry.path())?;
        files.entry(piece.to_string()).or_default().insert(n, rows);
    }
    if files.is_empty() {
        return Err(FingeringError::Dataset {
            path: dir.display().to_string(),
            reason: "no vio*_*.csv files".into(),
        });
    }
    Ok(files.into_iter().map(|(n, v)| align(n, v)).collect())
}

/// Aligns the violinists' files of one piece on (onset, pitch, occurrence).
fn align(name: String, by_violinist: BTreeMap<u32, Vec<Row>>) -> Piece {
    let keys = |rows: &Vec<Row>| -> Vec<(i64, u8)> { rows.iter().map(|r| (r.0, r.1)).collect() };
    let mut versions: BTreeMap<Vec<(i64, u8)>, usize> = BTreeMap::new();
    for rows in by_violinist.values() {
        *versions.entry(keys(rows)).or_default() += 1;
    }
    let reference = versions
        .iter()
        .max_by_key(|(k, n)| (**n, std::cmp::Reverse((*k).clone())))
        .map(|(k, _)| k.clone())
        .unwrap_or_default();
    let mut labels = vec![Vec::with_capacity(by_violinist.len()); reference.len()];
    let mut sequences = Vec::new();
    for rows in by_violinist.values() {
        let mut seen: BTreeMap<(i64, u8), Vec<Label>> = BTreeMap::new();
        for r in rows {
            seen.entry((r.0, r.1)).or_default().push(r.2);
        }
        let mut used: BTreeMap<(i64, u8), usize> = BTreeMap::new();
        for (k, slot) in reference.iter().zip(labels.iter_mut()) {
            let n = used.entry(*k).or_default();
            let label = seen.get(k).and_then(|v| v.get(*n)).copied();
            *n += 1;
            slot.push(label.filter(|l| l.string != 0));
        }
        sequences.push(rows.iter().map(|r| (r.1, r.2)).collect());
    }
    Piece {
        name,
        midi: reference.iter().map(|k| k.1).collect(),
        labels,
        sequences,
    }
}

/// Counts the pieces' fingerings into parameters with the given smoothing and weights
/// `[alpha, beta, lambda, mu, gamma_string, gamma_position]` (see [`LearnedParams`]).
pub fn fit(pieces: &[&Piece], h: [f64; 6]) -> LearnedParams {
    fit_with_fifths(pieces, h, None)
}

/// [`fit`], with each violinist's places also counted a fifth up on the next string and a
/// fifth down on the previous one (same position, finger and placement: the hand does the
/// same thing one string over) where that string exists, as emission counts only. With
/// `Some(w)` the real counts weigh `w` times a shifted one (alpha and beta are scaled by
/// `w` too, so the real counts keep their smoothing); `None` counts the real places only.
pub fn fit_with_fifths(pieces: &[&Piece], h: [f64; 6], fifths: Option<u32>) -> LearnedParams {
    let [alpha, beta, lambda, mu, gamma_string, gamma_position] = h;
    let w = fifths.unwrap_or(1).max(1);
    let mut p = LearnedParams {
        alpha: alpha * f64::from(w),
        beta: beta * f64::from(w),
        lambda,
        mu,
        gamma_string,
        gamma_position,
        ..LearnedParams::default()
    };
    let names: Vec<&str> = pieces.iter().map(|p| p.name.as_str()).collect();
    p.notes = vec![
        "Learned from the TNUA violin fingering dataset (Chen et al., IUI 2021,".into(),
        "github.com/Tsung-Ping/Violin-Fingering-Generation), 10 violinists.".into(),
        format!("Pieces used: {}.", names.join(", ")),
        "Written by `cargo run --release -p fingering --features train --example tnua`.".into(),
    ];
    for piece in pieces {
        for seq in &piece.sequences {
            let mut previous: Option<(u8, Fingering)> = None;
            let pitches: Vec<u8> = seq.iter().map(|s| s.0).collect();
            for (i, &(midi, label)) in seq.iter().enumerate() {
                let place = label.to_fingering(midi);
                if let Some(f) = place {
                    let ctx = context(&pitches, i);
                    *p.emission.entry((midi, ctx, f)).or_default() += w;
                    if fifths.is_some() {
                        for (m, g) in fifth_neighbours(midi, &f) {
                            *p.emission.entry((m, ctx, g)).or_default() += 1;
                        }
                    }
                    if let Some((pm, pf)) = previous {
                        let iv = interval_class(pm, midi);
                        let (ds, dp) = steps(&pf, &f);
                        *p.transition.entry((iv, ds, dp)).or_default() += w;
                        if ds == 0 && dp == 0 && !pf.is_open() && !f.is_open() {
                            *p.finger.entry((iv, pf.finger, f.finger)).or_default() += w;
                        }
                    }
                }
                previous = place.map(|f| (midi, f));
            }
        }
    }
    p
}

/// Sets `p`'s span context to `span` and counts, into `p.span_emission`, where each
/// violinist of `pieces` played each pitch per melodic context and span class
/// ([`crate::span::span_class`] of the violinist's own note sequence).
pub fn count_span(p: &mut LearnedParams, pieces: &[&Piece], span: SpanContext) {
    p.span = Some(span);
    p.span_emission.clear();
    for seq in pieces.iter().flat_map(|piece| &piece.sequences) {
        let pitches: Vec<u8> = seq.iter().map(|s| s.0).collect();
        for (i, &(midi, label)) in seq.iter().enumerate() {
            if let Some(f) = label.to_fingering(midi) {
                let class = span_class(&pitches, i, span.ahead, span.behind);
                let key = (midi, context(&pitches, i), class, f);
                *p.span_emission.entry(key).or_default() += 1;
            }
        }
    }
}

/// The place `f` (playing `midi`) moved one string up and one string down, with the pitch
/// it then plays, where that string exists and the pitch is one the learned model plays.
fn fifth_neighbours(midi: u8, f: &Fingering) -> Vec<(u8, Fingering)> {
    let mut out = Vec::new();
    for step in [-1i8, 1] {
        let Some(string) = ViolinString::from_number((f.string.number() as i8 + step) as u8) else {
            continue;
        };
        let m = i16::from(midi) + i16::from(string.open_midi()) - i16::from(f.string.open_midi());
        let Ok(m) = u8::try_from(m) else { continue };
        let g = Fingering { string, ..*f };
        if g.midi() == m && crate::learned::learned_places(m).contains(&g) {
            out.push((m, g));
        }
    }
    out
}

/// Agreement of planned fingerings with the violinists, summed over notes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Agreement {
    /// Notes with at least one violinist's label.
    pub notes: usize,
    /// Sum over notes of the share of violinists on the same string.
    pub string: f64,
    /// Sum over notes of the share on the same string and position (open = open).
    pub string_position: f64,
    /// Notes where at least one violinist agrees on string and position.
    pub any: usize,
}

impl Agreement {
    /// Adds another piece's sums.
    pub fn add(&mut self, o: &Agreement) {
        self.notes += o.notes;
        self.string += o.string;
        self.string_position += o.string_position;
        self.any += o.any;
    }

    /// Scores one planned place against the violinists' labels of its note (`given`
    /// non-empty; an empty slice adds nothing).
    pub fn add_note(&mut self, f: &Fingering, given: &[Label]) {
        if given.is_empty() {
            return;
        }
        let n = given.len() as f64;
        let sp = given.iter().filter(|l| l.same_string_position(f)).count();
        self.notes += 1;
        self.string += given.iter().filter(|l| l.same_string(f)).count() as f64 / n;
        self.string_position += sp as f64 / n;
        self.any += usize::from(sp > 0);
    }

    /// A Markdown table row: `| name | notes | string | string+position | any |`.
    pub fn markdown_row(&self, name: &str) -> String {
        let (s, sp, any) = self.shares();
        format!("| {name} | {} | {s:.3} | {sp:.3} | {any:.3} |", self.notes)
    }

    /// (string, string+position, any) as shares of the notes.
    pub fn shares(&self) -> (f64, f64, f64) {
        let n = self.notes.max(1) as f64;
        (
            self.string / n,
            self.string_position / n,
            self.any as f64 / n,
        )
    }
}

/// How far `plan` (one place per note of `piece`) agrees with the violinists.
pub fn agreement(piece: &Piece, plan: &[Fingering]) -> Agreement {
    let mut a = Agreement::default();
    for (labels, f) in piece.labels.iter().zip(plan) {
        let given: Vec<Label> = labels.iter().flatten().copied().collect();
        a.add_note(f, &given);
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_place_moves_a_fifth_with_its_string() {
        // D5 (74) with the 1st finger on the A string in 3rd position.
        let f = Fingering::new(ViolinString::A, 3, 1);
        assert_eq!(f.midi(), 74);
        let moved = fifth_neighbours(74, &f);
        assert_eq!(
            moved,
            vec![
                (67, Fingering::new(ViolinString::D, 3, 1)),
                (81, Fingering::new(ViolinString::E, 3, 1)),
            ]
        );
        // The G string has no string below it, and the open E none above.
        let g = Fingering::open(ViolinString::G, 1);
        assert_eq!(
            fifth_neighbours(55, &g),
            vec![(62, Fingering::open(ViolinString::D, 1))]
        );
        let e = Fingering::open(ViolinString::E, 1);
        assert_eq!(
            fifth_neighbours(76, &e),
            vec![(69, Fingering::open(ViolinString::A, 1))]
        );
    }

    #[test]
    fn a_note_is_scored_against_every_label_given() {
        let l = |string, position, finger| Label {
            string,
            position,
            finger,
        };
        // D5 (74) with the 3rd finger on the A string in 1st position.
        let planned = Fingering::new(ViolinString::A, 1, 3);
        let mut a = Agreement::default();
        a.add_note(&planned, &[]);
        assert_eq!(a, Agreement::default());
        // Two of four on the A string, one of them in 1st position; one on the open D
        // string (another string), one on the D string in 3rd.
        a.add_note(&planned, &[l(3, 1, 3), l(3, 3, 1), l(2, 3, 4), l(2, 1, 0)]);
        assert_eq!(a.notes, 1);
        assert!((a.string - 0.5).abs() < 1e-12);
        assert!((a.string_position - 0.25).abs() < 1e-12);
        assert_eq!(a.any, 1);
        // No label on the planned string and position: "any" stays.
        a.add_note(&planned, &[l(3, 3, 1)]);
        assert_eq!((a.notes, a.any), (2, 1));
        assert_eq!(a.markdown_row("p"), "| p | 2 | 0.750 | 0.125 | 0.500 |");
        let (string, string_position, any) = a.shares();
        assert!((string - 0.75).abs() < 1e-12);
        assert!((string_position - 0.125).abs() < 1e-12);
        assert!((any - 0.5).abs() < 1e-12);
    }

    #[test]
    fn shifted_counts_join_the_emissions_only() {
        let label = Label {
            string: 3,
            position: 3,
            finger: 1,
        };
        let piece = Piece {
            name: "p".into(),
            midi: vec![74, 74],
            labels: vec![vec![Some(label)]; 2],
            sequences: vec![vec![(74, label), (74, label)]],
        };
        let h = [1.0, 1.0, 1.0, 1.0, 0.0, 0.0];
        let plain = fit(&[&piece], h);
        let shifted = fit_with_fifths(&[&piece], h, Some(3));
        assert_eq!(plain.emission.len(), 2); // two contexts of (74, A3-1)
        assert_eq!(shifted.emission.len(), 6); // and of (67, D3-1), (81, E3-1)
        assert!(shifted
            .emission
            .iter()
            .all(|((m, _, _), n)| *n == if *m == 74 { 3 } else { 1 }));
        assert_eq!(shifted.transition.values().sum::<u32>(), 3);
        assert_eq!(plain.transition.values().sum::<u32>(), 1);
        assert_eq!((shifted.alpha, shifted.beta), (3.0, 3.0));
    }
}
