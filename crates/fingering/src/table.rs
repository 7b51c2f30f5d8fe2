//! Fingering tables: for each MIDI pitch, the places that play it, in preference order.

use crate::error::FingeringError;
use crate::fingering::Fingering;
use crate::physical;
use crate::string::ViolinString;

/// The original design's table (its appendix 1), as published; see `data/original_table.tsv`.
pub const ORIGINAL_TABLE_TSV: &str = include_str!("../data/original_table.tsv");

/// For each MIDI pitch, the places ([`Fingering`]s) that play it, in the table's order
/// (the greedy planner takes the first one listed in a position).
///
/// * [`FingeringTable::original`] — the original design's coarse table, G3..=E6 (34 notes,
///   positions 1..=7); a semitone and its neighbour often share entries.
/// * [`FingeringTable::physical`] — every place of the physical model
///   ([`crate::physical`]), G3..=A7 (MIDI 55..=105), exact to the semitone.
/// * [`FingeringTable::from_tsv`] — any table in the original's TSV form.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FingeringTable {
    /// The lowest pitch with an entry (meaningless when `ranges` is empty).
    lowest: u8,
    /// `places[start..end]` for pitch `lowest + i`.
    ranges: Vec<(u32, u32)>,
    places: Vec<Fingering>,
}

impl FingeringTable {
    /// The original design's table, parsed from the embedded [`ORIGINAL_TABLE_TSV`].
    ///
    /// Each `string-position-finger` entry is kept as published; its [`crate::Placement`]
    /// is the one (low/normal/high) whose pitch under the physical model is nearest the
    /// note it is listed for, so [`Fingering::midi`] is exact wherever the physical model
    /// allows and otherwise one semitone off (the table is coarse: e.g. A#3 shares A3's
    /// `1-1-1`, A#4 lists the open A string). Tests check that the embedded text parses
    /// without error; a malformed line would be skipped here rather than panic.
    pub fn original() -> FingeringTable {
        let (entries, _errors) = parse_tsv(ORIGINAL_TABLE_TSV);
        FingeringTable::from_entries(entries)
    }

    /// Every place of the physical model for G3..=A7 (MIDI 55..=105), ordered by string
    /// (G first) then position (half position first); see [`crate::physical`].
    pub fn physical() -> FingeringTable {
        let mut places = Vec::new();
        let mut ranges = Vec::new();
        for midi in physical::LOWEST_MIDI..=physical::HIGHEST_MIDI {
            let start = places.len() as u32;
            crate::places::push_places_for(midi, &mut places);
            ranges.push((start, places.len() as u32));
        }
        FingeringTable {
            lowest: physical::LOWEST_MIDI,
            ranges,
            places,
        }
    }

    /// Reads a table in the original's TSV form: `#` comment lines, an optional header
    /// line starting with `note`, then one line per pitch: `name midi places...` separated
    /// by tabs or spaces, e.g. `C#4 61 1-1-3 1-2-2 1-3-1`. A place is
    /// `string-position-finger` (string 1..=4 = G D A E, finger 0 = open, 1..=4; the
    /// position must exist on the string, see [`physical::max_position`]). The name must
    /// spell the MIDI number (`C#4`, `Db4` or `C4#` for 61) and a pitch may appear once.
    /// Placements are resolved as in [`FingeringTable::original`].
    pub fn from_tsv(text: &str) -> Result<FingeringTable, FingeringError> {
        let (entries, errors) = parse_tsv(text);
        match errors.into_iter().next() {
            Some(error) => Err(error),
            None => Ok(FingeringTable::from_entries(entries)),
        }
    }

    /// The places that play `midi`, in the table's order; empty if none does.
    pub fn places(&self, midi: u8) -> &[Fingering] {
        let Some(index) = midi.checked_sub(self.lowest) else {
            return &[];
        };
        match self.ranges.get(usize::from(index)) {
            Some(&(start, end)) => self.places.get(start as usize..end as usize).unwrap_or(&[]),
            None => &[],
        }
    }

    /// The pitches that have at least one place, ascending.
    pub fn pitches(&self) -> impl Iterator<Item = u8> + '_ {
        self.ranges
            .iter()
            .zip(self.lowest..=u8::MAX)
            .filter(|((start, end), _)| end > start)
            .map(|(_, midi)| midi)
    }

    /// The number of pitches with at least one place.
    pub fn len(&self) -> usize {
        self.pitches().count()
    }

    /// `true` if no pitch has a place.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The largest number of places listed for one pitch.
    pub fn max_places(&self) -> usize {
        self.ranges
            .iter()
            .map(|&(start, end)| (end - start) as usize)
            .max()
            .unwrap_or(0)
    }

    /// Builds the table from `(midi, places)` entries with distinct pitches.
    fn from_entries(mut entries: Vec<(u8, Vec<Fingering>)>) -> FingeringTable {
        entries.sort_by_key(|(midi, _)| *midi);
        let lowest = entries.first().map_or(0, |(midi, _)| *midi);
        let mut places = Vec::new();
        let mut ranges = Vec::new();
        for (midi, list) in entries {
            let index = usize::from(midi - lowest);
            let at = places.len() as u32;
            ranges.resize(index, (at, at));
            places.extend(list);
            ranges.push((at, places.len() as u32));
        }
        FingeringTable {
            lowest,
            ranges,
            places,
        }
    }
}

/// Parses TSV text into `(midi, places)` entries, skipping (and reporting) bad lines.
fn parse_tsv(text: &str) -> (Vec<(u8, Vec<Fingering>)>, Vec<FingeringError>) {
    let mut entries: Vec<(u8, Vec<Fingering>)> = Vec::new();
    let mut errors = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut fields = line.split_whitespace();
        let (Some(name), Some(midi_text)) = (fields.next(), fields.next()) else {
            errors.push(invalid(
                i,
                format!("expected `name midi places...`, got {line:?}"),
            ));
            continue;
        };
        if name.eq_ignore_ascii_case("note") {
            continue;
        }
        match parse_row(name, midi_text, fields) {
            Ok((midi, _)) if entries.iter().any(|(m, _)| *m == midi) => {
                errors.push(invalid(i, format!("MIDI {midi} is listed twice")));
            }
            Ok(entry) => entries.push(entry),
            Err(reason) => errors.push(invalid(i, reason)),
        }
    }
    (entries, errors)
}

fn invalid(zero_based_line: usize, reason: String) -> FingeringError {
    FingeringError::InvalidTable {
        line: zero_based_line + 1,
        reason,
    }
}

fn parse_row<'a>(
    name: &str,
    midi_text: &str,
    places: impl Iterator<Item = &'a str>,
) -> Result<(u8, Vec<Fingering>), String> {
    let midi: u8 = midi_text
        .parse()
        .ok()
        .filter(|m| *m <= 127)
        .ok_or_else(|| format!("MIDI number must be 0..=127, got {midi_text:?}"))?;
    let named = note_name_to_midi(name).ok_or_else(|| format!("bad note name {name:?}"))?;
    if named != i32::from(midi) {
        return Err(format!("note name {name} is MIDI {named}, not {midi}"));
    }
    let list = places
        .map(|text| parse_place(text, midi))
        .collect::<Result<Vec<_>, _>>()?;
    if list.is_empty() {
        return Err(format!("{name} lists no place"));
    }
    Ok((midi, list))
}

/// `string-position-finger` → a place, its placement resolved against `midi`.
fn parse_place(text: &str, midi: u8) -> Result<Fingering, String> {
    let numbers: Vec<Option<u8>> = text.split('-').map(|n| n.parse().ok()).collect();
    let [Some(s), Some(position), Some(finger)] = numbers[..] else {
        return Err(format!("place {text:?} is not `string-position-finger`"));
    };
    let string = ViolinString::from_number(s)
        .ok_or_else(|| format!("place {text:?}: string must be 1..=4"))?;
    if finger > 4 {
        return Err(format!("place {text:?}: finger must be 0..=4"));
    }
    if position > physical::max_position(string) {
        return Err(format!(
            "place {text:?}: the {string} string has positions 0..={}",
            physical::max_position(string)
        ));
    }
    Ok(nearest_placement(string, position, finger, midi))
}

/// The placement of `finger` in `position` whose pitch is nearest `midi` (ties: normal).
pub(crate) fn nearest_placement(
    string: ViolinString,
    position: u8,
    finger: u8,
    midi: u8,
) -> Fingering {
    let mut best = Fingering::new(string, position, finger);
    for &placement in physical::placements(finger) {
        let candidate = Fingering::with_placement(string, position, finger, placement);
        let distance = |f: &Fingering| (i32::from(f.midi()) - i32::from(midi)).abs();
        if distance(&candidate) < distance(&best) {
            best = candidate;
        }
    }
    best
}

/// The MIDI key of a note name in scientific pitch notation: `C4` → 60, `C#4` / `Cs4` /
/// `Db4` / `C4#` → 61; `None` if it is not a note name (the key is not range-checked).
///
/// ```
/// assert_eq!(fingering::note_name_to_midi("A4"), Some(69));
/// assert_eq!(fingering::note_name_to_midi("As3"), Some(58));
/// assert_eq!(fingering::note_name_to_midi("violin"), None);
/// ```
pub fn note_name_to_midi(name: &str) -> Option<i32> {
    let mut chars = name.chars();
    let class = match chars.next()?.to_ascii_uppercase() {
        'C' => 0,
        'D' => 2,
        'E' => 4,
        'F' => 5,
        'G' => 7,
        'A' => 9,
        'B' => 11,
        _ => return None,
    };
    let rest = chars.as_str();
    let sharp = rest.strip_prefix('#').or_else(|| rest.strip_prefix('s'));
    let (alter, rest) = if let Some(r) = sharp {
        (1, r)
    } else if let Some(r) = rest.strip_prefix('b') {
        (-1, r)
    } else if let Some(r) = rest.strip_suffix('#') {
        (1, r)
    } else {
        (0, rest)
    };
    // Octaves far outside MIDI's are refused rather than overflowing.
    let octave: i32 = rest.parse().ok().filter(|o: &i32| o.abs() <= 100)?;
    Some(12 * (octave + 1) + class + alter)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn note_names() {
        assert_eq!(note_name_to_midi("C4"), Some(60));
        assert_eq!(note_name_to_midi("C#4"), Some(61));
        assert_eq!(note_name_to_midi("Db4"), Some(61));
        assert_eq!(note_name_to_midi("C4#"), Some(61));
        assert_eq!(note_name_to_midi("A7"), Some(105));
        assert_eq!(note_name_to_midi("H4"), None);
        assert_eq!(note_name_to_midi("C"), None);
        assert_eq!(note_name_to_midi("A999999999"), None);
        assert_eq!(note_name_to_midi("Cs4"), Some(61));
    }

    #[test]
    fn tsv_errors_name_the_line() {
        let bad = [
            ("C4\t61\t1-1-3", 1),                     // name does not spell the number
            ("C4\t60\t5-1-3", 1),                     // no string 5
            ("C4\t60\t1-1-7", 1),                     // no finger 7
            ("C4\t60\t1-11-3", 1),                    // no 11th position on the G string
            ("C4\t60\t1-1", 1),                       // not string-position-finger
            ("C4\t60", 1),                            // no place
            ("# c\nC4\t60\t1-1-3\nC4\t60\t1-1-3", 3), // twice
            ("C4\t300\t1-1-3", 1),                    // not a MIDI number
        ];
        for (text, line) in bad {
            match FingeringTable::from_tsv(text) {
                Err(FingeringError::InvalidTable { line: l, .. }) => assert_eq!(l, line, "{text}"),
                other => panic!("{text:?} gave {other:?}"),
            }
        }
    }

    #[test]
    fn a_small_table_reads_with_gaps_between_pitches() {
        let t = FingeringTable::from_tsv("note\tmidi\tplaces\nG3 55 1-1-0\nB3 59 1-1-2 1-2-1\n")
            .unwrap();
        assert_eq!(t.len(), 2);
        assert_eq!(t.pitches().collect::<Vec<_>>(), vec![55, 59]);
        assert_eq!(t.places(55), &[Fingering::open(ViolinString::G, 1)]);
        assert!(t.places(56).is_empty());
        assert!(t.places(54).is_empty());
        assert!(t.places(60).is_empty());
        assert_eq!(t.places(59).len(), 2);
        assert_eq!(t.max_places(), 2);
    }

    #[test]
    fn an_empty_table_has_no_places() {
        let t = FingeringTable::from_tsv("# nothing\n").unwrap();
        assert!(t.is_empty());
        assert!(t.places(60).is_empty());
        assert_eq!(t.max_places(), 0);
    }
}
