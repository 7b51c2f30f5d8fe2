//! The checks of [`crate::Performance::new`] on lists of times and on notes.

use crate::error::PerformanceError;
use crate::note::Note;

/// `value` (entry `index` of `field`) is finite and inside `[0, duration_s]`.
fn check_time(
    field: &'static str,
    index: usize,
    value: f64,
    duration_s: f64,
) -> Result<(), PerformanceError> {
    if !value.is_finite() {
        return Err(PerformanceError::NonFinite {
            field,
            index,
            value,
        });
    }
    if !(0.0..=duration_s).contains(&value) {
        return Err(PerformanceError::OutOfRange {
            field,
            index,
            value,
            duration_s,
        });
    }
    Ok(())
}

pub(crate) fn check_times(
    field: &'static str,
    times: &[f64],
    duration_s: f64,
) -> Result<(), PerformanceError> {
    for (index, &value) in times.iter().enumerate() {
        check_time(field, index, value, duration_s)?;
        if index > 0 && value <= times[index - 1] {
            return Err(PerformanceError::Unsorted {
                field,
                index,
                value,
            });
        }
    }
    Ok(())
}

pub(crate) fn check_notes(notes: &mut [Note], duration_s: f64) -> Result<(), PerformanceError> {
    for (index, n) in notes.iter().enumerate() {
        for (field, value) in [("notes.onset_s", n.onset_s), ("notes.offset_s", n.offset_s)] {
            check_time(field, index, value, duration_s)?;
        }
        if n.offset_s <= n.onset_s {
            return Err(PerformanceError::EmptyNote {
                index,
                onset_s: n.onset_s,
                offset_s: n.offset_s,
            });
        }
        if n.midi > 127 {
            return Err(PerformanceError::InvalidMidi {
                index,
                midi: n.midi,
            });
        }
        if index > 0 && n.onset_s <= notes[index - 1].onset_s {
            return Err(PerformanceError::Unsorted {
                field: "notes.onset_s",
                index,
                value: n.onset_s,
            });
        }
    }
    // Monophonic line: a new note ends the previous one.
    for i in 1..notes.len() {
        let next_onset = notes[i].onset_s;
        let prev = &mut notes[i - 1];
        prev.offset_s = prev.offset_s.min(next_onset);
    }
    Ok(())
}

/// The second voice of a performance ([`crate::PerformanceParts::double_stops`]): times
/// finite and inside `[0, duration_s]`, each note ending after it starts, pitches 0..=127,
/// onsets in order (equal onsets allowed: a chord's notes).
pub(crate) fn check_double_stops(notes: &[Note], duration_s: f64) -> Result<(), PerformanceError> {
    let mut previous = f64::NEG_INFINITY;
    for (index, n) in notes.iter().enumerate() {
        check_time("double_stops.onset_s", index, n.onset_s, duration_s)?;
        check_time("double_stops.offset_s", index, n.offset_s, duration_s)?;
        let problem = if n.offset_s <= n.onset_s {
            Some(format!(
                "ends at {} s, not after its onset {} s",
                n.offset_s, n.onset_s
            ))
        } else if n.midi > 127 {
            Some(format!("MIDI pitch {}; MIDI pitches are 0..=127", n.midi))
        } else if n.onset_s < previous {
            Some(format!(
                "starts at {} s, before the note listed before it ({previous} s); sort by onset",
                n.onset_s
            ))
        } else {
            None
        };
        if let Some(problem) = problem {
            return Err(PerformanceError::InvalidDoubleStop { index, problem });
        }
        previous = n.onset_s;
    }
    Ok(())
}
