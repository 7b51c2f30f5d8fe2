//! The learned planner's parameters: smoothed counts of where violinists put each pitch
//! and how they move between notes, in a small TSV file.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use crate::error::FingeringError;
use crate::fingering::Fingering;
use crate::placement::Placement;
use crate::span::{SpanContext, SPAN_CLASSES};
use crate::string::ViolinString;

/// Melodic contexts a note's place depends on: the interval from the previous note and to
/// the next one, each in six classes (none, leap down ≥ 3, step down, repeat, step up, leap
/// up ≥ 3).
pub const CONTEXTS: usize = 36;

/// The shipped parameters (`data/learned_tnua.tsv`), learned from the TNUA violin fingering
/// dataset (Chen et al., IUI 2021, github.com/Tsung-Ping/Violin-Fingering-Generation); the
/// file names the pieces used.
pub const LEARNED_PARAMS_TSV: &str = include_str!("../data/learned_tnua.tsv");

/// Intervals are counted in classes -13..=13 semitones (larger leaps share the end classes).
pub const MAX_INTERVAL: i8 = 13;
/// Position changes are counted in classes -7..=7.
pub const MAX_POSITION_STEP: i8 = 7;

/// Counts and smoothing of the learned planner ([`crate::LearnedPlanner`]):
///
/// * `emission[(pitch, context, place)]`: how often a violinist played `pitch` at `place`
///   in that melodic context ([`crate::learned::context`]);
/// * `transition[(interval, string step, position step)]`: how often consecutive notes
///   `interval` semitones apart moved that many strings and positions;
/// * `finger[(interval, previous finger, finger)]` for consecutive notes in the same
///   position on the same string;
/// * `alpha`, `beta`: smoothing weights (pseudo-counts spread over the back-off
///   distributions); `lambda`: weight of the transition costs against the emission costs;
///   `mu`: weight of the finger pairs; `gamma_string`, `gamma_position`: rewards for a
///   place whose hand frame also covers the neighbouring notes (violinists choose a
///   position for a group of notes, not note by note);
/// * `span`, `span_emission[(pitch, context, span class, place)]`: where a passage is going
///   ([`crate::span`]); `None` in files written before it existed.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LearnedParams {
    /// Pseudo-counts of the emission back-off.
    pub alpha: f64,
    /// Pseudo-counts of the transition back-off.
    pub beta: f64,
    /// Weight of the transition costs.
    pub lambda: f64,
    /// Weight of the finger-to-finger costs.
    pub mu: f64,
    /// Reward per neighbouring note (within 4 notes, `learned::WINDOW`) that the
    /// same string in the same position also plays.
    pub gamma_string: f64,
    /// Reward per neighbouring note that the same position plays on any string.
    pub gamma_position: f64,
    /// Where each pitch was played.
    pub emission: BTreeMap<(u8, u8, Fingering), u32>,
    /// String and position steps per interval class.
    pub transition: BTreeMap<(i8, i8, i8), u32>,
    /// Finger pairs per interval class within one position and string.
    pub finger: BTreeMap<(i8, u8, u8), u32>,
    /// How the span context is read and weighed (`None`: not used).
    pub span: Option<SpanContext>,
    /// Where each pitch was played per melodic context and span class.
    pub span_emission: BTreeMap<(u8, u8, u8, Fingering), u32>,
    /// Free text lines (`#` comments): provenance.
    pub notes: Vec<String>,
}

fn placement_code(p: Placement) -> i8 {
    p.semitones()
}

fn placement_of(code: i64) -> Option<Placement> {
    match code {
        -1 => Some(Placement::Low),
        0 => Some(Placement::Normal),
        1 => Some(Placement::High),
        _ => None,
    }
}

impl LearnedParams {
    /// The shipped parameters ([`LEARNED_PARAMS_TSV`]).
    pub fn shipped() -> Result<LearnedParams, FingeringError> {
        LearnedParams::from_tsv(LEARNED_PARAMS_TSV)
    }

    /// Writes the parameters as TSV: `#` lines, then `hyper alpha beta lambda mu
    /// gamma_string gamma_position`,
    /// `e pitch context string position finger placement count`, `t interval dstring dposition
    /// count` and `f interval finger_from finger_to count` rows; with a span context, a
    /// `span ahead behind alpha weight` row and `s pitch context class string position finger
    /// placement count` rows.
    pub fn to_tsv(&self) -> String {
        let mut out = String::new();
        for line in &self.notes {
            let _ = writeln!(out, "# {line}");
        }
        let _ = writeln!(
            out,
            "hyper\t{}\t{}\t{}\t{}\t{}\t{}",
            self.alpha, self.beta, self.lambda, self.mu, self.gamma_string, self.gamma_position
        );
        for ((pitch, ctx, f), n) in &self.emission {
            let _ = writeln!(out, "e\t{pitch}\t{ctx}\t{}\t{n}", place_columns(f));
        }
        for ((i, s, p), n) in &self.transition {
            let _ = writeln!(out, "t\t{i}\t{s}\t{p}\t{n}");
        }
        for ((i, a, b), n) in &self.finger {
            let _ = writeln!(out, "f\t{i}\t{a}\t{b}\t{n}");
        }
        if let Some(span) = &self.span {
            let SpanContext {
                ahead,
                behind,
                alpha,
                weight,
            } = span;
            let _ = writeln!(out, "span\t{ahead}\t{behind}\t{alpha}\t{weight}");
        }
        for ((pitch, ctx, class, f), n) in &self.span_emission {
            let _ = writeln!(out, "s\t{pitch}\t{ctx}\t{class}\t{}\t{n}", place_columns(f));
        }
        out
    }

    /// Reads the form [`LearnedParams::to_tsv`] writes.
    pub fn from_tsv(text: &str) -> Result<LearnedParams, FingeringError> {
        let mut params = LearnedParams::default();
        let mut has_hyper = false;
        for (i, line) in text.lines().enumerate() {
            let err = |reason: String| FingeringError::InvalidTable {
                line: i + 1,
                reason,
            };
            let line = line.trim();
            if let Some(note) = line.strip_prefix('#') {
                params.notes.push(note.trim().to_string());
                continue;
            }
            if line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line.split('\t').collect();
            let (&kind, rest) = fields
                .split_first()
                .ok_or_else(|| err("empty line".into()))?;
            if kind == "hyper" {
                let v: Vec<f64> = rest
                    .iter()
                    .map(|s| s.parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|e| err(format!("hyper: {e}")))?;
                match v[..] {
                    [a, b, l, m, gs, gp] if v.iter().all(|x| x.is_finite() && *x >= 0.0) => {
                        (params.alpha, params.beta, params.lambda, params.mu) = (a, b, l, m);
                        (params.gamma_string, params.gamma_position) = (gs, gp);
                        has_hyper = true;
                    }
                    _ => return Err(err("hyper needs 6 finite values ≥ 0".into())),
                }
                continue;
            }
            if kind == "span" {
                params.span = Some(span_row(rest).map_err(err)?);
                continue;
            }
            let v: Vec<i64> = rest
                .iter()
                .map(|s| s.parse::<i64>())
                .collect::<Result<_, _>>()
                .map_err(|e| err(format!("{kind}: {e}")))?;
            let small = |x: i64, lo: i64, hi: i64| (lo..=hi).contains(&x);
            match (kind, &v[..]) {
                ("e", &[pitch, ctx, s, pos, f, pl, n]) => {
                    let place = place_row(pitch, ctx, [s, pos, f, pl]).map_err(err)?;
                    params
                        .emission
                        .insert((pitch as u8, ctx as u8, place), count(n, &err)?);
                }
                ("s", &[pitch, ctx, class, s, pos, f, pl, n])
                    if small(class, 0, SPAN_CLASSES as i64 - 1) =>
                {
                    let place = place_row(pitch, ctx, [s, pos, f, pl]).map_err(err)?;
                    let key = (pitch as u8, ctx as u8, class as u8, place);
                    params.span_emission.insert(key, count(n, &err)?);
                }
                ("t", &[iv, s, p, n])
                    if small(iv, -13, 13) && small(s, -3, 3) && small(p, -7, 7) =>
                {
                    params
                        .transition
                        .insert((iv as i8, s as i8, p as i8), count(n, &err)?);
                }
                ("f", &[iv, a, b, n]) if small(iv, -13, 13) && small(a, 0, 4) && small(b, 0, 4) => {
                    params
                        .finger
                        .insert((iv as i8, a as u8, b as u8), count(n, &err)?);
                }
                _ => return Err(err(format!("unknown or malformed `{kind}` row"))),
            }
        }
        if !has_hyper {
            return Err(FingeringError::InvalidTable {
                line: 0,
                reason: "no `hyper` row".into(),
            });
        }
        Ok(params)
    }
}

/// A place as the `e` and `s` rows write it: `string position finger placement`.
fn place_columns(f: &Fingering) -> String {
    format!(
        "{}\t{}\t{}\t{}",
        f.string.number(),
        f.position,
        f.finger,
        placement_code(f.placement)
    )
}

/// The place of an `e` or `s` row: `[string, position, finger, placement]`, checked to play
/// `pitch` (`context` checked too).
fn place_row(pitch: i64, context: i64, [s, pos, f, pl]: [i64; 4]) -> Result<Fingering, String> {
    let small = |x: i64, lo: i64, hi: i64| (lo..=hi).contains(&x);
    let string = u8::try_from(s)
        .ok()
        .and_then(ViolinString::from_number)
        .ok_or_else(|| format!("string {s} is not 1..=4"))?;
    let placement = placement_of(pl).ok_or_else(|| format!("placement {pl}"))?;
    if !(small(pitch, 0, 127)
        && small(context, 0, CONTEXTS as i64 - 1)
        && small(pos, 0, 20)
        && small(f, 0, 4))
    {
        return Err("pitch, context, position or finger out of range".into());
    }
    let place = Fingering::with_placement(string, pos as u8, f as u8, placement);
    if place.midi() != pitch as u8 {
        return Err(format!("place does not play MIDI {pitch}"));
    }
    Ok(place)
}

/// The `span ahead behind alpha weight` row's values (notes ahead and behind at most 64).
fn span_row(rest: &[&str]) -> Result<SpanContext, String> {
    let [ahead, behind, alpha, weight] = rest else {
        return Err("span needs 4 values: ahead behind alpha weight".into());
    };
    let notes = |s: &str| match s.parse::<usize>() {
        Ok(n) if n <= 64 => Ok(n),
        _ => Err(format!("span: {s} is not a number of notes 0..=64")),
    };
    let real = |s: &str| match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        _ => Err(format!("span: {s} is not a finite value ≥ 0")),
    };
    Ok(SpanContext {
        ahead: notes(ahead)?,
        behind: notes(behind)?,
        alpha: real(alpha)?,
        weight: real(weight)?,
    })
}

fn count(n: i64, err: &dyn Fn(String) -> FingeringError) -> Result<u32, FingeringError> {
    u32::try_from(n).map_err(|_| err(format!("count {n} is not 0..=u32::MAX")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tsv_round_trip_and_errors() {
        let mut p = LearnedParams {
            alpha: 5.0,
            beta: 10.0,
            lambda: 1.5,
            mu: 0.5,
            gamma_string: 0.25,
            gamma_position: 0.5,
            notes: vec!["made by a test".into()],
            ..LearnedParams::default()
        };
        p.emission
            .insert((71, 3, Fingering::new(ViolinString::A, 1, 1)), 7);
        p.transition.insert((2, 0, 0), 3);
        p.finger.insert((2, 1, 2), 4);
        let back = LearnedParams::from_tsv(&p.to_tsv()).unwrap();
        assert_eq!(back, p);
        p.span = Some(SpanContext {
            ahead: 4,
            behind: 0,
            alpha: 2.0,
            weight: 1.0,
        });
        p.span_emission
            .insert((74, 3, 13, Fingering::new(ViolinString::A, 3, 1)), 5);
        assert_eq!(LearnedParams::from_tsv(&p.to_tsv()).unwrap(), p);
        let hyper = "hyper\t1\t1\t1\t1\t0\t0\n";
        for bad in [
            "span\t4\t0\t2\n",
            "span\t4\t0\t2\tNaN\n",
            "span\t4000\t0\t2\t1\n",
            "s\t71\t3\t36\t3\t3\t1\t0\t5\n",
            "s\t72\t3\t13\t3\t3\t1\t0\t5\n",
        ] {
            assert!(
                LearnedParams::from_tsv(&format!("{hyper}{bad}")).is_err(),
                "{bad}"
            );
        }
        assert!(LearnedParams::from_tsv("e\t71\t3\t1\t1\t0\t7\n").is_err()); // no hyper
        let wrong_pitch = "hyper\t1\t1\t1\t1\t0\t0\ne\t72\t0\t3\t1\t1\t0\t7\n";
        assert!(LearnedParams::from_tsv(wrong_pitch).is_err());
        assert!(LearnedParams::from_tsv("hyper\t1\t1\tx\t1\t0\t0\n").is_err());
    }

    #[test]
    fn the_shipped_parameters_parse() {
        let p = LearnedParams::shipped().unwrap();
        assert!(p.emission.len() > 100 && p.transition.len() > 100);
        assert!(p.notes.iter().any(|n| n.contains("TNUA")));
    }
}
