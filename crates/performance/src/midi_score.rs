//! [`MidiScore`]: what a MIDI file says, as read by [`crate::midi`].

use crate::meter::Meter;

/// One note as the file has it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MidiNote {
    /// Note-on time in seconds.
    pub onset_s: f64,
    /// Note-off time in seconds.
    pub offset_s: f64,
    /// MIDI pitch (after transposition, when asked for).
    pub midi: u8,
    /// Note-on velocity 1..=127.
    pub velocity: u8,
    /// MIDI channel 0..=15 (never 9, drums).
    pub channel: u8,
}

/// What a MIDI file says: its notes (time order; a chord's notes highest first), beats,
/// downbeats and meter.
#[derive(Debug, Clone, PartialEq)]
pub struct MidiScore {
    /// Every note of the file but the drums'.
    pub notes: Vec<MidiNote>,
    /// Every beat, in seconds.
    pub beats_s: Vec<f64>,
    /// Every downbeat, in seconds.
    pub downbeats_s: Vec<f64>,
    /// The first bar's meter.
    pub meter: Meter,
    /// `true` when the meter comes from a time signature, `false` when inferred.
    pub meter_from_file: bool,
    /// The tempo at the first note, bpm.
    pub tempo_bpm: f64,
    /// The last note's end plus a short release tail, seconds.
    pub duration_s: f64,
    /// How many notes were moved by octaves into the violin's range.
    pub transposed: usize,
}
