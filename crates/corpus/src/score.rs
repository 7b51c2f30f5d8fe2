//! Written music before any timing is applied: the étude generator's [`Etude`] (in beats)
//! and the general [`Score`] (in quarter notes, with bars) that études and repertoire become.

use performance::TimeSignature;
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

    /// The written time signature.
    pub fn time_signature(self) -> TimeSignature {
        match self {
            Meter::TwoFour => TimeSignature::new(2, 4),
            Meter::ThreeFour => TimeSignature::new(3, 4),
            Meter::FourFour => TimeSignature::new(4, 4),
            Meter::SixEight => TimeSignature::new(6, 8),
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

/// One bar of a [`Score`]: where it starts, how long it is as written (a pickup bar is
/// shorter than its signature) and its time signature.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bar {
    /// Start in quarter notes from the beginning of the score.
    pub start_q: f64,
    /// Written length in quarter notes.
    pub len_q: f64,
    /// Time signature in force.
    pub time_signature: TimeSignature,
}

impl Bar {
    /// A bar shorter than its signature: a pickup (anacrusis) or an incomplete last bar.
    pub fn is_partial(&self) -> bool {
        self.len_q + 1e-6 < self.time_signature.bar_quarters()
    }
}

/// One note of a [`Score`], in quarter notes. Chords keep their top pitch in `midi` and
/// the others in `lower`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartNote {
    /// Start in quarter notes.
    pub start_q: f64,
    /// Written length in quarter notes.
    pub dur_q: f64,
    /// MIDI pitch (the top one of a chord).
    pub midi: u8,
    /// Lower pitches of a chord (double stop), highest first.
    pub lower: Vec<u8>,
    /// Continues the previous note's slur (no bow change).
    pub slurred_from_previous: bool,
    /// Dynamic 0 (pp) ..= 1 (ff) from the score's marks, if it has any.
    pub dynamic: Option<f32>,
    /// Accent (or sf-type dynamic on the note).
    pub accent: bool,
    /// Staccato, staccatissimo or spiccato.
    pub staccato: bool,
    /// Fermata on the note.
    pub fermata: bool,
}

impl PartNote {
    /// End in quarter notes.
    pub fn end_q(&self) -> f64 {
        self.start_q + self.dur_q
    }
}

/// Where a score comes from (written to the corpus manifest).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Provenance {
    /// Collection, e.g. "oneills1850" or "etude".
    pub collection: String,
    /// Title.
    pub title: String,
    /// The file and part it was read from.
    pub source: String,
    /// Licence of the music and its encoding.
    pub license: String,
}

/// A written part with its bar structure: what the corpus performs. Études and repertoire
/// (`crate::repertoire`) both become one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Score {
    /// The work this part belongs to (splits are made by work), e.g. "mozart/k80".
    pub work: String,
    /// This part's id, e.g. "mozart/k80/movement1/violin1".
    pub id: String,
    /// Bars in time order.
    pub bars: Vec<Bar>,
    /// Notes in time order, monophonic (chords are one note with `lower` pitches).
    pub notes: Vec<PartNote>,
    /// Tempo marked in the score, in notated beats per minute.
    pub tempo_bpm: Option<f64>,
    /// Source and licence.
    pub provenance: Provenance,
}

impl Score {
    /// End of the last bar (or note), in quarter notes.
    pub fn total_q(&self) -> f64 {
        let bars = self.bars.last().map_or(0.0, |b| b.start_q + b.len_q);
        let notes = self.notes.last().map_or(0.0, PartNote::end_q);
        bars.max(notes)
    }

    /// The time signature of the first complete bar (or the first bar).
    pub fn main_time_signature(&self) -> TimeSignature {
        self.bars
            .iter()
            .find(|b| !b.is_partial())
            .or(self.bars.first())
            .map_or(TimeSignature::new(4, 4), |b| b.time_signature)
    }

    /// Every notated beat as `(position in quarters, is a downbeat)`. A pickup bar's beats
    /// are counted back from its end; a partial bar's first beat is not a downbeat.
    pub fn beats_q(&self) -> Vec<(f64, bool)> {
        let mut out = Vec::new();
        for (i, bar) in self.bars.iter().enumerate() {
            let beat = bar.time_signature.beat_quarters();
            let full = bar.time_signature.bar_quarters();
            // A short first bar is a pickup: its beats sit where they would in a full bar.
            let shift = if i == 0 && bar.is_partial() {
                full - bar.len_q
            } else {
                0.0
            };
            let mut k = (shift / beat).ceil();
            while k * beat - shift < bar.len_q - 1e-6 {
                let q = bar.start_q + k * beat - shift;
                out.push((q, k == 0.0 && shift == 0.0));
                k += 1.0;
            }
        }
        out
    }

    /// Bars `first..first + count` as a score of their own, starting at 0 (notes that start
    /// inside them; a slur into the first note is cut there).
    pub fn excerpt(&self, first: usize, count: usize) -> Score {
        let end = (first + count).min(self.bars.len());
        let first = first.min(end);
        let bars = &self.bars[first..end];
        let (Some(b0), Some(bl)) = (bars.first(), bars.last()) else {
            return Score {
                bars: Vec::new(),
                notes: Vec::new(),
                ..self.clone()
            };
        };
        let (from, to) = (b0.start_q, bl.start_q + bl.len_q);
        let mut notes: Vec<PartNote> = self
            .notes
            .iter()
            .filter(|n| n.start_q >= from - 1e-6 && n.start_q < to - 1e-6)
            .map(|n| PartNote {
                start_q: n.start_q - from,
                dur_q: n.dur_q.min(to - n.start_q),
                ..n.clone()
            })
            .collect();
        if let Some(n) = notes.first_mut() {
            n.slurred_from_previous = false;
        }
        Score {
            bars: bars
                .iter()
                .map(|b| Bar {
                    start_q: b.start_q - from,
                    ..*b
                })
                .collect(),
            notes,
            ..self.clone()
        }
    }
}

impl Etude {
    /// The étude as a [`Score`] (beats become quarter notes; 6/8 beats are dotted quarters).
    pub fn to_score(&self, id: &str) -> Score {
        let ts = self.meter.time_signature();
        let q = ts.beat_quarters();
        let bar_q = ts.bar_quarters();
        Score {
            work: id.to_string(),
            id: id.to_string(),
            bars: (0..self.bars)
                .map(|b| Bar {
                    start_q: f64::from(b) * bar_q,
                    len_q: bar_q,
                    time_signature: ts,
                })
                .collect(),
            notes: self
                .notes
                .iter()
                .map(|n| PartNote {
                    start_q: n.start_beats * q,
                    dur_q: n.dur_beats * q,
                    midi: n.midi,
                    lower: Vec::new(),
                    slurred_from_previous: n.slurred_from_previous,
                    dynamic: Some(n.dynamic),
                    accent: n.accent,
                    staccato: false,
                    fermata: false,
                })
                .collect(),
            tempo_bpm: Some(self.tempo_bpm),
            provenance: Provenance {
                collection: "etude".into(),
                title: format!("{} {} étude", self.mode, self.meter.name()),
                source: "generated by corpus::etude".into(),
                license: "generated (no third-party material)".into(),
            },
        }
    }
}
