//! MIDI files in: notes and timing from the file, bowing from slurs/articulation heuristics,
//! arousal from velocity — the MIDI-driven route (seed 003, MIDI2Pose) to a [`Timeline`].
//!
//! Rules (documented so users can shape their MIDI):
//! * all channels but 10 (drums) are merged; overlapping notes are reduced to one line:
//!   onsets within 30 ms form a chord of which the highest note is kept, a note that starts
//!   while another sounds cuts it (legato);
//! * pitches below G3 or above A7 are moved by octaves into the violin's range;
//! * **bowing**: a note continues the previous note's bow (a slur) when it follows within
//!   30 ms (legato), the slur has fewer than 4 notes (8 when notes are shorter than 0.2 s),
//!   the bow has been moving for less than 2 s, it is not the first note of a bar, and its
//!   velocity is within 20 of the previous one; every other note starts a new stroke;
//! * beats from the tempo map (quarter notes; dotted quarters in 6/8, 9/8, 12/8) and
//!   downbeats from the time signature (4/4 when the file has none);
//! * dynamics from velocity (v / 127); arousal from [`crate::arousal_proxy`].

use std::path::{Path, PathBuf};

use midly::{MetaMessage, MidiMessage, Smf, Timing, TrackEventKind};

use crate::error::MidiError;
use crate::note::Note;
use crate::timeline::{arousal_proxy, TimedNote, Timeline};

const CHORD_S: f64 = 0.03;
const LEGATO_GAP_S: f64 = 0.03;
const TAIL_S: f64 = 0.6;
const LOWEST: u8 = 55;
const HIGHEST: u8 = 105;

/// Reads a MIDI file into a [`Timeline`].
pub fn timeline_from_midi_file(path: impl AsRef<Path>) -> Result<Timeline, MidiError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| MidiError {
        path: path.into(),
        reason: format!("cannot read ({e})"),
    })?;
    timeline_from_midi(&bytes).map_err(|e| MidiError {
        path: path.into(),
        reason: e.reason,
    })
}

fn midi_err(reason: impl Into<String>) -> MidiError {
    MidiError {
        path: PathBuf::from("<memory>"),
        reason: reason.into(),
    }
}

/// Tick → seconds through the tempo map.
struct TempoMap {
    /// (tick, seconds at tick, microseconds per quarter from tick on).
    segments: Vec<(u64, f64, f64)>,
    ticks_per_quarter: f64,
    timecode_ticks_per_s: Option<f64>,
}

impl TempoMap {
    fn seconds(&self, tick: u64) -> f64 {
        if let Some(tps) = self.timecode_ticks_per_s {
            return tick as f64 / tps;
        }
        let i = self
            .segments
            .partition_point(|s| s.0 <= tick)
            .saturating_sub(1);
        let (t0, s0, us) = self.segments[i];
        s0 + (tick - t0) as f64 * us / 1e6 / self.ticks_per_quarter
    }

    fn bpm_at_s(&self, t: f64) -> f64 {
        if self.timecode_ticks_per_s.is_some() {
            return 120.0;
        }
        let i = self
            .segments
            .partition_point(|s| s.1 <= t)
            .saturating_sub(1);
        60e6 / self.segments[i].2
    }
}

/// Parses MIDI bytes (SMF format 0/1/2, or RIFF-wrapped) into a [`Timeline`].
pub fn timeline_from_midi(bytes: &[u8]) -> Result<Timeline, MidiError> {
    let smf = Smf::parse(bytes).map_err(|e| {
        midi_err(format!(
            "not a MIDI file ({e}); export a Standard MIDI File (.mid)"
        ))
    })?;
    let (ticks_per_quarter, timecode) = match smf.header.timing {
        Timing::Metrical(t) => (f64::from(t.as_int().max(1)), None),
        Timing::Timecode(fps, sub) => (1.0, Some(f64::from(fps.as_f32()) * f64::from(sub.max(1)))),
    };
    let mut tempos: Vec<(u64, f64)> = Vec::new();
    let mut time_sig: Option<(u64, u32, u32)> = None;
    let mut raw: Vec<(u64, u64, u8, u8)> = Vec::new(); // (on tick, off tick, key, velocity)
    for track in &smf.tracks {
        let mut tick = 0u64;
        let mut open: Vec<(u8, u8, u64, u8)> = Vec::new(); // (channel, key, on tick, vel)
        for ev in track {
            tick += u64::from(ev.delta.as_int());
            match ev.kind {
                TrackEventKind::Meta(MetaMessage::Tempo(us)) => {
                    tempos.push((tick, f64::from(us.as_int().max(1))))
                }
                TrackEventKind::Meta(MetaMessage::TimeSignature(num, den_pow, _, _))
                    if time_sig.is_none() =>
                {
                    time_sig = Some((tick, u32::from(num.max(1)), 1u32 << den_pow.min(6)));
                }
                TrackEventKind::Midi { channel, message } => {
                    let ch = channel.as_int();
                    if ch == 9 {
                        continue;
                    }
                    match message {
                        MidiMessage::NoteOn { key, vel } if vel.as_int() > 0 => {
                            open.push((ch, key.as_int(), tick, vel.as_int()));
                        }
                        MidiMessage::NoteOn { key, .. } | MidiMessage::NoteOff { key, .. } => {
                            if let Some(i) =
                                open.iter().position(|o| o.0 == ch && o.1 == key.as_int())
                            {
                                let (_, k, on, v) = open.remove(i);
                                if tick > on {
                                    raw.push((on, tick, k, v));
                                }
                            }
                        }
                        _ => {}
                    }
                }
                _ => {}
            }
        }
    }
    if raw.is_empty() {
        return Err(midi_err(
            "contains no notes (channel 10, drums, is ignored)",
        ));
    }
    tempos.sort_by_key(|t| t.0);
    let mut segments = vec![(0u64, 0.0f64, 500_000.0f64)];
    for (tick, us) in tempos {
        let s = {
            let (t0, s0, u0) = *segments.last().unwrap_or(&(0, 0.0, 500_000.0));
            s0 + (tick - t0) as f64 * u0 / 1e6 / ticks_per_quarter
        };
        if segments.last().is_some_and(|l| l.0 == tick) {
            segments.pop();
        }
        segments.push((tick, s, us));
    }
    let map = TempoMap {
        segments,
        ticks_per_quarter,
        timecode_ticks_per_s: timecode,
    };
    raw.sort_by(|a, b| a.0.cmp(&b.0).then(b.2.cmp(&a.2)));
    let notes = reduce_to_line(&raw, &map);
    let last_tick = raw.iter().map(|r| r.1).max().unwrap_or(0);
    let (sig_tick, num, den) = time_sig.unwrap_or((0, 4, 4));
    let compound = den == 8 && num % 3 == 0 && num > 3;
    let beat_ticks = if compound { 1.5 } else { 4.0 / den as f64 } * ticks_per_quarter;
    let beats_per_bar = if compound { num / 3 } else { num };
    let (mut beats_s, mut downbeats_s) = (Vec::new(), Vec::new());
    let mut k = 0u64;
    loop {
        let tick = sig_tick as f64 + k as f64 * beat_ticks;
        if tick > last_tick as f64 + 1e-9 || k > 1_000_000 {
            break;
        }
        let t = map.seconds(tick.round() as u64);
        beats_s.push(t);
        if k.is_multiple_of(u64::from(beats_per_bar.max(1))) {
            downbeats_s.push(t);
        }
        k += 1;
    }
    let notes = assign_bowing(notes, &downbeats_s);
    let duration_s = notes.last().map_or(0.0, |n| n.note.offset_s) + TAIL_S;
    let arousal_2hz = arousal_proxy(&notes, duration_s);
    Ok(Timeline {
        duration_s,
        tempo_bpm: map.bpm_at_s(0.0),
        notes,
        beats_s,
        downbeats_s,
        arousal_2hz,
    })
}

/// One melodic line: chords keep their highest note, overlaps cut the earlier note.
fn reduce_to_line(raw: &[(u64, u64, u8, u8)], map: &TempoMap) -> Vec<TimedNote> {
    let mut out: Vec<TimedNote> = Vec::new();
    for &(on, off, key, vel) in raw {
        let onset_s = map.seconds(on);
        let offset_s = map.seconds(off);
        if let Some(prev) = out.last_mut() {
            if onset_s - prev.note.onset_s < CHORD_S {
                continue; // lower note of a chord (sorted highest first)
            }
            if prev.note.offset_s > onset_s {
                prev.note.offset_s = onset_s;
            }
        }
        let mut midi = key;
        while midi < LOWEST {
            midi += 12;
        }
        while midi > HIGHEST {
            midi -= 12;
        }
        out.push(TimedNote {
            note: Note::new(onset_s, offset_s, midi),
            bow_change: true,
            dynamic: f32::from(vel) / 127.0,
            accent: false,
        });
    }
    out
}

fn assign_bowing(mut notes: Vec<TimedNote>, downbeats_s: &[f64]) -> Vec<TimedNote> {
    let mut slur_len = 0usize;
    let mut stroke_start = 0.0;
    for i in 0..notes.len() {
        let on_downbeat = downbeats_s
            .iter()
            .any(|d| (d - notes[i].note.onset_s).abs() < 0.02);
        let slurred = i > 0 && {
            let prev = &notes[i - 1];
            let cur = &notes[i];
            let short = cur.note.offset_s - cur.note.onset_s < 0.2;
            cur.note.onset_s - prev.note.offset_s < LEGATO_GAP_S
                && slur_len < if short { 8 } else { 4 }
                && cur.note.offset_s - stroke_start < 2.0
                && !on_downbeat
                && (cur.dynamic - prev.dynamic).abs() * 127.0 <= 20.0
        };
        if slurred {
            slur_len += 1;
        } else {
            slur_len = 1;
            stroke_start = notes[i].note.onset_s;
        }
        notes[i].bow_change = !slurred;
        notes[i].accent = on_downbeat && !slurred;
    }
    notes
}

#[cfg(test)]
mod tests {
    use super::*;
    use midly::num::{u15, u24, u28, u4, u7};
    use midly::{Format, Header, TrackEvent};

    fn ev(delta: u32, kind: TrackEventKind<'static>) -> TrackEvent<'static> {
        TrackEvent {
            delta: u28::new(delta),
            kind,
        }
    }

    fn note_on(key: u8, vel: u8) -> TrackEventKind<'static> {
        TrackEventKind::Midi {
            channel: u4::new(0),
            message: MidiMessage::NoteOn {
                key: u7::new(key),
                vel: u7::new(vel),
            },
        }
    }

    fn note_off(key: u8) -> TrackEventKind<'static> {
        TrackEventKind::Midi {
            channel: u4::new(0),
            message: MidiMessage::NoteOff {
                key: u7::new(key),
                vel: u7::new(0),
            },
        }
    }

    /// 3/4 at 100 bpm (600 000 µs), 480 ticks per quarter: bar 1 three détaché quarters,
    /// bar 2 six legato eighths, bar 3 a half note with a low G2 (moved up an octave).
    fn file() -> Vec<u8> {
        let mut t = vec![
            ev(
                0,
                TrackEventKind::Meta(MetaMessage::Tempo(u24::new(600_000))),
            ),
            ev(
                0,
                TrackEventKind::Meta(MetaMessage::TimeSignature(3, 2, 24, 8)),
            ),
        ];
        for k in [67, 69, 71] {
            t.push(ev(0, note_on(k, 80)));
            t.push(ev(400, note_off(k)));
            t.push(ev(80, TrackEventKind::Meta(MetaMessage::Marker(b""))));
        }
        for k in [72, 74, 76, 74, 72, 71] {
            t.push(ev(0, note_on(k, 70)));
            t.push(ev(240, note_off(k)));
        }
        t.push(ev(0, note_on(43, 90)));
        t.push(ev(960, note_off(43)));
        t.push(ev(0, TrackEventKind::Meta(MetaMessage::EndOfTrack)));
        let smf = Smf {
            header: Header::new(Format::SingleTrack, Timing::Metrical(u15::new(480))),
            tracks: vec![t],
        };
        let mut bytes = Vec::new();
        smf.write_std(&mut bytes).unwrap();
        bytes
    }

    #[test]
    fn notes_timing_bowing_and_bars() {
        let t = timeline_from_midi(&file()).unwrap();
        assert_eq!(t.notes.len(), 10);
        assert!((t.notes[1].note.onset_s - 0.6).abs() < 1e-9);
        assert_eq!(t.notes[9].note.midi, 55); // G2 moved into range
                                              // Détaché quarters: three strokes; legato eighths slurred after the bar's first note.
        let changes: Vec<bool> = t.notes.iter().map(|n| n.bow_change).collect();
        assert_eq!(changes[..3], [true, true, true]);
        assert!(changes[3] && !changes[4] && !changes[5]);
        assert!(changes[9]); // downbeat of bar 3
        assert!((t.downbeats_s[1] - 1.8).abs() < 1e-9);
        assert_eq!(t.beats_s.len(), 9);
        assert!(t.arousal_2hz.iter().all(|a| (-1.0..=1.0).contains(a)));
    }

    #[test]
    fn bad_files_are_errors() {
        assert!(matches!(
            timeline_from_midi(b"not midi"),
            Err(MidiError { .. })
        ));
        let empty = Smf {
            header: Header::new(Format::SingleTrack, Timing::Metrical(u15::new(480))),
            tracks: vec![vec![ev(0, TrackEventKind::Meta(MetaMessage::EndOfTrack))]],
        };
        let mut bytes = Vec::new();
        empty.write_std(&mut bytes).unwrap();
        let err = timeline_from_midi(&bytes).unwrap_err();
        assert!(err.to_string().contains("no notes"));
        let mut cut = file();
        cut.truncate(30);
        assert!(timeline_from_midi(&cut).is_err());
        assert!(timeline_from_midi_file("/no/such.mid")
            .unwrap_err()
            .to_string()
            .contains("/no/such.mid"));
    }
}
