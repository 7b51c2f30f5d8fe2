//! A written étude: meter, tempo and notes in beats, before any timing is applied.

use serde::{Deserialize, Serialize};

/// Time signature. The beat is the quarter note, except in 6/8 where it is the dotted
/// quarter (two beats per bar, three eighths each).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Meter {
    /// 2/4.
    TwoFour,
    /// 3/4.
    ThreeFour,
    /// 4/4.
    FourFour,
    /// 6/8, counted in two.
    SixEight,
}

impl Meter {
    /// All meters.
    pub const ALL: [Meter; 4] = [
        Meter::TwoFour,
        Meter::ThreeFour,
        Meter::FourFour,
        Meter::SixEight,
    ];

    /// Beats per bar (the downbeat is beat 0 of each bar).
    pub fn beats_per_bar(self) -> u32 {
        match self {
            Meter::TwoFour | Meter::SixEight => 2,
            Meter::ThreeFour => 3,
            Meter::FourFour => 4,
        }
    }

    /// Subdivisions of one beat used by rhythms (2 for simple meters, 3 for 6/8).
    pub fn beat_division(self) -> u32 {
        match self {
            Meter::SixEight => 3,
            _ => 2,
        }
    }

    /// The conventional name, e.g. `"3/4"`.
    pub fn name(self) -> &'static str {
        match self {
            Meter::TwoFour => "2/4",
            Meter::ThreeFour => "3/4",
            Meter::FourFour => "4/4",
            Meter::SixEight => "6/8",
        }
    }
}

/// One written note. Rests are the gaps between notes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScoreNote {
    /// Start, in beats from the beginning of the étude.
    pub start_beats: f64,
    /// Written length in beats.
    pub dur_beats: f64,
    /// MIDI pitch.
    pub midi: u8,
    /// True when this note continues the previous note's slur (same bow stroke, no bow change).
    pub slurred_from_previous: bool,
    /// Dynamic level 0 (pp) ..= 1 (ff).
    pub dynamic: f32,
    /// Accented (stronger attack).
    pub accent: bool,
}

impl ScoreNote {
    /// End in beats.
    pub fn end_beats(&self) -> f64 {
        self.start_beats + self.dur_beats
    }
}

/// A complete étude.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Etude {
    /// Time signature.
    pub meter: Meter,
    /// Nominal tempo in beats per minute.
    pub tempo_bpm: f64,
    /// Tonic pitch class 0 (C) ..= 11 (B).
    pub tonic: u8,
    /// Mode name ("major", "minor", "dorian", …).
    pub mode: String,
    /// Number of bars.
    pub bars: u32,
    /// Notes in time order, non-overlapping.
    pub notes: Vec<ScoreNote>,
}

impl Etude {
    /// Length in beats.
    pub fn total_beats(&self) -> f64 {
        f64::from(self.bars * self.meter.beats_per_bar())
    }
}
