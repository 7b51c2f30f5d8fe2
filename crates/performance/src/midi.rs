//! MIDI files in: the notes exactly as the file has them, beats and bars from its tempo map
//! and time signatures ([`MidiScore`]), and the MIDI-driven route (seed 003, MIDI2Pose) to a
//! [`Timeline`] with bowing from slur/articulation rules and arousal from velocity.
//!
//! Rules (documented so users can shape their MIDI):
//! * all channels but 10 (drums) are read; [`MidiScore::notes`] keeps every note as in the
//!   file (overlapping notes are double stops); the [`Timeline`] for motion reduces them to
//!   one line: onsets within 30 ms form a chord of which the highest note is kept, a note
//!   that starts while another sounds cuts it (legato);
//! * pitches below G3 (MIDI 55) or above A7 (105) are refused, naming the first one, unless
//!   [`MidiOptions::transpose_into_range`] moves them by octaves into the range;
//! * **bowing** ([`MidiBowing`]): a note continues the previous note's bow (a slur) when
//!   it starts within 1 ms of the previous note's end (legato: a separate bow leaves a
//!   gap), the slur has fewer than 6 notes (8 when notes are shorter than 0.2 s), the bow
//!   has been moving for less than 3 s, it is not the first note of a bar, and its
//!   velocity is within 10 of the previous one; every other note starts a new stroke;
//! * **notated timing** ([`timing_is_notated`]): in a file whose notes touch as written
//!   (fewer than 20 % of consecutive notes apart by a gap) and whose onsets sit on the beat
//!   grid, as a notation program exports them, the gaps cannot tell slurs from separate
//!   bows, so [`MidiBowing::NOTATED`] applies: every note takes a new bow except notes
//!   shorter than 0.125 s (ornaments, the fastest runs), slurred up to 6. Against real
//!   players' bowing (the YTVF dataset, `ytvf_bowing` in `violin-train`) that gets 0.69
//!   of their bow changes (F) where slurring whatever touches got 0.42;
//! * where a bar would then start up-bow, the two strokes before it
//!   are hooked into one bow when that is playable ([`crate::hooks_for_downbeats`]);
//!   directions follow [`crate::bow_directions`];
//! * beats from the tempo map and every time signature (quarter notes, dotted quarters in
//!   6/8, 9/8, 12/8); a file without a time signature gets the bar length (2, 3 or 4
//!   beats) and phase that put the longest and loudest notes on downbeats;
//! * dynamics from velocity (v / 127); arousal from [`crate::arousal_proxy`] (velocity and
//!   note density).
//!
//! Refused, with one line naming the reason (the caller adds the file): not a Standard MIDI
//! File (or a corrupt one, e.g. a bad delta time), files over 64 MiB, division 0, a tempo
//! outside 5..=1000 bpm, no notes or only percussion, more than 200 000 notes, more than
//! an hour of music, or more than five minutes of silence before or between notes.

use std::path::{Path, PathBuf};

use midly::{MetaMessage, MidiMessage, Smf, Timing, TrackEventKind};

pub use crate::midi_line::{
    separated_share, timeline_from_score, timeline_from_score_with, timing_is_notated, MidiBowing,
};
pub use crate::midi_score::{MidiNote, MidiScore};

use crate::error::MidiError;
use crate::timeline::Timeline;

/// The largest file read.
pub const MAX_FILE_BYTES: u64 = 64 << 20;
/// The most notes a file may have.
pub const MAX_NOTES: usize = 200_000;
/// The longest piece read by default, in seconds ([`MidiOptions::max_duration_s`]).
pub const MAX_DURATION_S: f64 = 3600.0;
/// The longest silence before or between notes, in seconds.
pub const MAX_SILENCE_S: f64 = 300.0;
/// Tempi outside this range (bpm) are refused.
pub const TEMPO_RANGE_BPM: (f64, f64) = (5.0, 1000.0);
const LOWEST: u8 = 55;
const HIGHEST: u8 = 105;

/// How a MIDI file is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MidiOptions {
    /// Move notes outside G3..=A7 by octaves into the range instead of refusing the file.
    pub transpose_into_range: bool,
    /// A file whose notes sound past this many seconds is refused (a corrupt delta time can
    /// otherwise ask for hours of silence). Default [`MAX_DURATION_S`].
    pub max_duration_s: u32,
}

impl Default for MidiOptions {
    fn default() -> Self {
        MidiOptions {
            transpose_into_range: false,
            max_duration_s: MAX_DURATION_S as u32,
        }
    }
}

const TAIL_S: f64 = 0.6;

pub(crate) fn midi_err(reason: impl Into<String>) -> MidiError {
    MidiError {
        path: PathBuf::from("<memory>"),
        reason: reason.into(),
    }
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, MidiError> {
    let err = |reason: String| MidiError {
        path: path.into(),
        reason,
    };
    let size = std::fs::metadata(path)
        .map_err(|e| err(format!("cannot read ({e})")))?
        .len();
    if size > MAX_FILE_BYTES {
        return Err(err(format!(
            "is {} MiB; a MIDI file for one violin is far smaller (at most {} MiB are read)",
            size >> 20,
            MAX_FILE_BYTES >> 20
        )));
    }
    std::fs::read(path).map_err(|e| err(format!("cannot read ({e})")))
}

fn with_path(path: &Path, e: MidiError) -> MidiError {
    MidiError {
        path: path.into(),
        reason: e.reason,
    }
}

/// Reads a MIDI file into a [`MidiScore`].
pub fn score_from_midi_file(
    path: impl AsRef<Path>,
    options: &MidiOptions,
) -> Result<MidiScore, MidiError> {
    let path = path.as_ref();
    score_from_midi(&read_bytes(path)?, options).map_err(|e| with_path(path, e))
}

/// Reads a MIDI file into a [`Timeline`] (one line, bowing, arousal), refusing notes
/// outside the violin's range.
pub fn timeline_from_midi_file(path: impl AsRef<Path>) -> Result<Timeline, MidiError> {
    timeline_from_midi_file_with(path, &MidiOptions::default())
}

/// [`timeline_from_midi_file`] with options.
pub fn timeline_from_midi_file_with(
    path: impl AsRef<Path>,
    options: &MidiOptions,
) -> Result<Timeline, MidiError> {
    let path = path.as_ref();
    let score = score_from_midi(&read_bytes(path)?, options).map_err(|e| with_path(path, e))?;
    Ok(crate::midi_line::timeline_from_score(&score))
}

/// Parses MIDI bytes into a [`Timeline`], refusing notes outside the violin's range.
pub fn timeline_from_midi(bytes: &[u8]) -> Result<Timeline, MidiError> {
    let score = score_from_midi(bytes, &MidiOptions::default())?;
    Ok(crate::midi_line::timeline_from_score(&score))
}

/// Tick → seconds through the tempo map.
struct TempoMap {
    /// (tick, seconds at tick, microseconds per quarter from tick on).
    segments: Vec<(u64, f64, f64)>,
    ticks_per_quarter: f64,
}

impl TempoMap {
    fn new(mut tempos: Vec<(u64, f64)>, ticks_per_quarter: f64) -> TempoMap {
        tempos.sort_by_key(|t| t.0);
        let mut segments = vec![(0u64, 0.0f64, 500_000.0f64)];
        for (tick, us) in tempos {
            let (t0, s0, u0) = *segments.last().unwrap_or(&(0, 0.0, 500_000.0));
            let s = s0 + (tick - t0) as f64 * u0 / 1e6 / ticks_per_quarter;
            if segments.last().is_some_and(|l| l.0 == tick) {
                segments.pop();
            }
            segments.push((tick, s, us));
        }
        TempoMap {
            segments,
            ticks_per_quarter,
        }
    }

    fn segment(&self, tick: f64) -> (u64, f64, f64) {
        let i = self
            .segments
            .partition_point(|s| s.0 as f64 <= tick)
            .saturating_sub(1);
        self.segments.get(i).copied().unwrap_or((0, 0.0, 500_000.0))
    }

    fn seconds(&self, tick: f64) -> f64 {
        let (t0, s0, us) = self.segment(tick);
        s0 + (tick - t0 as f64) * us / 1e6 / self.ticks_per_quarter
    }

    fn bpm_at_tick(&self, tick: f64) -> f64 {
        60e6 / self.segment(tick).2
    }
}

/// What one pass over the tracks collects.
#[derive(Default)]
struct Raw {
    tempos: Vec<(u64, f64)>,
    signatures: Vec<(u64, u32, u32)>,
    /// (on tick, off tick, key, velocity, channel)
    notes: Vec<(u64, u64, u8, u8, u8)>,
    drum_notes: usize,
}

fn collect(smf: &Smf) -> Result<Raw, MidiError> {
    let mut raw = Raw::default();
    for track in &smf.tracks {
        let mut tick = 0u64;
        let mut open: Vec<(u8, u8, u64, u8)> = Vec::new(); // (channel, key, on tick, vel)
        for ev in track {
            tick += u64::from(ev.delta.as_int());
            match ev.kind {
                TrackEventKind::Meta(MetaMessage::Tempo(us)) => {
                    raw.tempos.push((tick, f64::from(us.as_int())))
                }
                TrackEventKind::Meta(MetaMessage::TimeSignature(num, den_pow, _, _)) => {
                    raw.signatures
                        .push((tick, u32::from(num.max(1)), 1u32 << den_pow.min(5)));
                }
                TrackEventKind::Midi { channel, message } => {
                    let ch = channel.as_int();
                    match message {
                        MidiMessage::NoteOn { vel, .. } if ch == 9 && vel.as_int() > 0 => {
                            raw.drum_notes += 1;
                        }
                        _ if ch == 9 => {}
                        MidiMessage::NoteOn { key, vel } if vel.as_int() > 0 => {
                            open.push((ch, key.as_int(), tick, vel.as_int()));
                        }
                        MidiMessage::NoteOn { key, .. } | MidiMessage::NoteOff { key, .. } => {
                            if let Some(i) =
                                open.iter().position(|o| o.0 == ch && o.1 == key.as_int())
                            {
                                let (_, k, on, v) = open.remove(i);
                                if tick > on {
                                    raw.notes.push((on, tick, k, v, ch));
                                }
                            }
                        }
                        _ => {}
                    }
                    if raw.notes.len() > MAX_NOTES {
                        return Err(midi_err(format!(
                            "has more than {MAX_NOTES} notes; split it into pieces"
                        )));
                    }
                }
                _ => {}
            }
        }
    }
    Ok(raw)
}

/// Parses MIDI bytes (SMF format 0/1/2, or RIFF-wrapped) into a [`MidiScore`].
pub fn score_from_midi(bytes: &[u8], options: &MidiOptions) -> Result<MidiScore, MidiError> {
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(midi_err("is larger than 64 MiB"));
    }
    let smf = Smf::parse(bytes).map_err(|e| {
        midi_err(format!(
            "not a valid Standard MIDI File ({e}); export a .mid file again"
        ))
    })?;
    let (ticks_per_quarter, fixed_us) = match smf.header.timing {
        Timing::Metrical(t) if t.as_int() == 0 => {
            return Err(midi_err(
                "division (ticks per quarter note) is 0, so no event has a time",
            ))
        }
        Timing::Metrical(t) => (f64::from(t.as_int()), None),
        // SMPTE time: ticks are fractions of a second; beats on a 120 bpm grid.
        Timing::Timecode(fps, sub) => {
            let per_s = f64::from(fps.as_f32()) * f64::from(sub.max(1));
            (per_s / 2.0, Some(500_000.0))
        }
    };
    let raw = collect(&smf)?;
    if raw.notes.is_empty() {
        return Err(midi_err(if raw.drum_notes > 0 {
            "has only percussion notes (channel 10), nothing a violin plays"
        } else {
            "contains no notes"
        }));
    }
    let tempos = match fixed_us {
        Some(us) => vec![(0, us)],
        None => raw.tempos.clone(),
    };
    let map = TempoMap::new(tempos, ticks_per_quarter);
    check_tempi(&map)?;
    let mut notes: Vec<(u64, u64, u8, u8, u8)> = raw.notes;
    notes.sort_by(|a, b| a.0.cmp(&b.0).then(b.2.cmp(&a.2)).then(a.1.cmp(&b.1)));
    let mut out = Vec::with_capacity(notes.len());
    let mut transposed = 0;
    for &(on, off, key, velocity, channel) in &notes {
        let onset_s = map.seconds(on as f64);
        let mut midi = key;
        if !(LOWEST..=HIGHEST).contains(&key) {
            if !options.transpose_into_range {
                let count = notes
                    .iter()
                    .filter(|n| !(LOWEST..=HIGHEST).contains(&n.2))
                    .count();
                return Err(midi_err(format!(
                    "{count} note(s) outside the violin's range G3..A7 (MIDI 55..=105), the first MIDI {key} at {onset_s:.2} s; transpose the part, or ask for octave transposition (--transpose-into-range)"
                )));
            }
            while midi < LOWEST {
                midi += 12;
            }
            while midi > HIGHEST {
                midi -= 12;
            }
            transposed += 1;
        }
        out.push(MidiNote {
            onset_s,
            offset_s: map.seconds(off as f64),
            midi,
            velocity,
            channel,
        });
    }
    check_span(&out, f64::from(options.max_duration_s))?;
    let last_tick = notes.iter().map(|n| n.1).max().unwrap_or(0);
    let grid =
        crate::midi_line::beat_grid(&raw.signatures, &notes, ticks_per_quarter, last_tick, |t| {
            map.seconds(t)
        });
    let first_tick = notes.first().map_or(0, |n| n.0);
    let duration_s = out.iter().map(|n| n.offset_s).fold(0.0, f64::max) + TAIL_S;
    Ok(MidiScore {
        notes: out,
        beats_s: grid.beats_s,
        downbeats_s: grid.downbeats_s,
        meter: grid.meter,
        meter_from_file: grid.from_file,
        tempo_bpm: map.bpm_at_tick(first_tick as f64),
        duration_s,
        transposed,
    })
}

fn check_tempi(map: &TempoMap) -> Result<(), MidiError> {
    let (lo, hi) = TEMPO_RANGE_BPM;
    for &(tick, s, us) in &map.segments {
        if us <= 0.0 {
            return Err(midi_err(format!(
                "tempo event of 0 microseconds per quarter note (no tempo) at {s:.2} s (tick {tick}); set a tempo within {lo}..={hi} bpm"
            )));
        }
        let bpm = 60e6 / us;
        if !(lo..=hi).contains(&bpm) {
            return Err(midi_err(format!(
                "tempo {bpm:.0} bpm at {s:.2} s (tick {tick}) is outside {lo}..={hi} bpm"
            )));
        }
    }
    Ok(())
}

fn check_span(notes: &[MidiNote], max_duration_s: f64) -> Result<(), MidiError> {
    let mut sounding_until = 0.0f64;
    for n in notes {
        if n.onset_s - sounding_until > MAX_SILENCE_S {
            return Err(midi_err(format!(
                "has {:.0} minutes of silence between {sounding_until:.1} s and {:.1} s; cut the file to the music",
                (n.onset_s - sounding_until) / 60.0,
                n.onset_s
            )));
        }
        sounding_until = sounding_until.max(n.offset_s);
        if sounding_until > max_duration_s {
            return Err(midi_err(format!(
                "lasts more than {:.0} minutes (a note ends at {:.0} s); split it into pieces or raise --max-duration",
                max_duration_s / 60.0,
                sounding_until
            )));
        }
    }
    Ok(())
}
