//! MIDI reading: notes as in the file, beats and bars, bowing, and every bad input refused
//! with one line naming the reason, quickly.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Instant;

use performance::midi::{
    score_from_midi, timeline_from_midi, timeline_from_midi_file, timeline_from_score_with,
    MidiBowing, MidiOptions,
};

/// A variable-length quantity.
fn vlq(mut v: u32) -> Vec<u8> {
    let mut out = vec![(v & 0x7f) as u8];
    v >>= 7;
    while v > 0 {
        out.insert(0, 0x80 | (v & 0x7f) as u8);
        v >>= 7;
    }
    out
}

/// A Standard MIDI File, format 0, from (delta, event bytes) pairs.
fn smf(division: u16, events: &[(u32, Vec<u8>)]) -> Vec<u8> {
    let mut track = Vec::new();
    for (delta, bytes) in events {
        track.extend(vlq(*delta));
        track.extend(bytes);
    }
    track.extend([0x00, 0xff, 0x2f, 0x00]);
    smf_raw(division, track)
}

/// A format-0 file around raw track bytes.
fn smf_raw(division: u16, track: Vec<u8>) -> Vec<u8> {
    let mut out = b"MThd".to_vec();
    out.extend(6u32.to_be_bytes());
    out.extend(0u16.to_be_bytes());
    out.extend(1u16.to_be_bytes());
    out.extend(division.to_be_bytes());
    out.extend(b"MTrk");
    out.extend((track.len() as u32).to_be_bytes());
    out.extend(track);
    out
}

fn on(key: u8, vel: u8) -> Vec<u8> {
    vec![0x90, key, vel]
}
fn off(key: u8) -> Vec<u8> {
    vec![0x80, key, 0]
}
fn tempo(us: u32) -> Vec<u8> {
    let b = us.to_be_bytes();
    vec![0xff, 0x51, 0x03, b[1], b[2], b[3]]
}
fn time_sig(num: u8, den_pow: u8) -> Vec<u8> {
    vec![0xff, 0x58, 0x04, num, den_pow, 24, 8]
}

/// 3/4 at 100 bpm, 480 ticks per quarter: bar 1 three détaché quarters (400 ticks + 80
/// rest), bar 2 six legato eighths, bar 3 a half note D4 with a double stop B4 above.
fn waltz(with_signature: bool) -> Vec<u8> {
    let mut ev = vec![(0, tempo(600_000))];
    if with_signature {
        ev.push((0, time_sig(3, 2)));
    }
    let mut rest = 0;
    for k in [67, 69, 71] {
        ev.push((rest, on(k, 80)));
        ev.push((400, off(k)));
        rest = 80;
    }
    for k in [72, 74, 76, 74, 72, 71] {
        ev.push((rest, on(k, 70)));
        ev.push((240, off(k)));
        rest = 0;
    }
    ev.push((0, on(62, 90)));
    ev.push((0, on(71, 90)));
    ev.push((960, off(62)));
    ev.push((0, off(71)));
    smf(480, &ev)
}

#[test]
fn notes_are_kept_as_in_the_file_with_velocity_and_double_stops() {
    let score = score_from_midi(&waltz(true), &MidiOptions::default()).unwrap();
    assert_eq!(score.notes.len(), 11);
    assert!((score.notes[1].onset_s - 0.6).abs() < 1e-9);
    assert!((score.notes[0].offset_s - 0.5).abs() < 1e-9);
    assert_eq!(score.notes[0].velocity, 80);
    // The double stop: both notes, same onset, higher first.
    assert_eq!((score.notes[9].midi, score.notes[10].midi), (71, 62));
    assert_eq!(score.notes[9].onset_s, score.notes[10].onset_s);
    assert!(score.meter_from_file);
    assert_eq!(score.meter.beats_per_bar, 3);
    assert!((score.downbeats_s[1] - 1.8).abs() < 1e-9);
    assert_eq!(score.beats_s.len(), 9);
    assert!((score.tempo_bpm - 100.0).abs() < 1e-9);
}

#[test]
fn the_line_for_motion_keeps_the_top_note_and_slurs_by_the_rules() {
    let t = timeline_from_midi(&waltz(true)).unwrap();
    assert_eq!(t.notes.len(), 10);
    assert_eq!(t.notes[9].note.midi, 71);
    let changes: Vec<bool> = t.notes.iter().map(|n| n.bow_change).collect();
    // Détaché (a gap between notes), but three strokes would start bar 2 up-bow: the
    // third quarter is hooked onto the second.
    assert_eq!(changes[..3], [true, true, false]);
    // The six legato eighths of bar 2 make one slur (fewer than 6 notes before each).
    assert_eq!(changes[3..9], [true, false, false, false, false, false]);
    assert!(changes[9]); // downbeat of bar 3
    assert!(t.arousal_2hz.iter().all(|a| (-1.0..=1.0).contains(a)));
    // That slur starts on bar 2's downbeat, so nothing can be hooked before bar 3, which
    // starts up-bow. With slurs of at most 4 notes the eighths take two strokes, and every
    // bar that starts with a bow change starts down-bow.
    let score = score_from_midi(&waltz(true), &MidiOptions::default()).unwrap();
    let four = MidiBowing {
        max_slur_notes: 4,
        max_slur_notes_short: 4,
        ..MidiBowing::default()
    };
    let t = timeline_from_score_with(&score, &four);
    let changes: Vec<bool> = t.notes.iter().map(|n| n.bow_change).collect();
    assert_eq!(changes[3..9], [true, false, false, false, true, false]);
    let notes: Vec<performance::Note> = t.notes.iter().map(|n| n.note).collect();
    let bow_changes_s = t.bow_changes_s();
    let dirs = performance::bow_directions(&bow_changes_s, &notes, &t.downbeats_s);
    for (c, d) in bow_changes_s.iter().zip(&dirs) {
        if t.downbeats_s.iter().any(|b| (b - c).abs() < 0.02) {
            assert_eq!(*d, performance::BowDirection::Down, "bar at {c} s");
        }
    }
}

#[test]
fn a_file_without_time_signature_gets_its_meter_from_the_notes() {
    // Four waltz bars, long-short: a half note, then a quarter.
    let mut ev = vec![(0, tempo(500_000))];
    for _ in 0..4 {
        ev.push((0, on(67, 90)));
        ev.push((960, off(67)));
        ev.push((0, on(71, 60)));
        ev.push((480, off(71)));
    }
    let score = score_from_midi(&smf(480, &ev), &MidiOptions::default()).unwrap();
    assert!(!score.meter_from_file);
    assert_eq!(score.meter.beats_per_bar, 3, "{:?}", score.downbeats_s);
    // The bar line after the last note counts too.
    assert_eq!(score.downbeats_s, vec![0.0, 1.5, 3.0, 4.5, 6.0]);
}

#[test]
fn time_signature_changes_move_the_bar_lines() {
    // 4/4 bar then 2/4 bars, quarter notes at 120 bpm.
    let mut ev = vec![(0, time_sig(4, 2))];
    for k in 0..8 {
        if k == 4 {
            ev.push((0, time_sig(2, 2)));
        }
        ev.push((0, on(69, 80)));
        ev.push((480, off(69)));
    }
    let score = score_from_midi(&smf(480, &ev), &MidiOptions::default()).unwrap();
    assert_eq!(score.downbeats_s, vec![0.0, 2.0, 3.0, 4.0]);
}

fn refused(bytes: &[u8], needle: &str) {
    let t = Instant::now();
    let err = score_from_midi(bytes, &MidiOptions::default()).unwrap_err();
    let text = err.to_string();
    assert!(text.contains(needle), "{text}");
    assert!(!text.contains('\n'), "one line: {text}");
    assert!(t.elapsed().as_secs_f64() < 1.0);
}

#[test]
fn bad_files_are_refused_with_the_reason() {
    refused(b"not midi", "not a valid Standard MIDI File");
    refused(&smf(480, &[]), "contains no notes");
    let drums = smf(480, &[(0, vec![0x99, 38, 100]), (240, vec![0x89, 38, 0])]);
    refused(&drums, "only percussion");
    let low = smf(480, &[(0, on(43, 80)), (480, off(43))]);
    refused(&low, "MIDI 43 at 0.00 s");
    let high = smf(
        480,
        &[
            (0, on(69, 80)),
            (480, off(69)),
            (0, on(110, 80)),
            (480, off(110)),
        ],
    );
    refused(&high, "1 note(s) outside the violin's range");
    refused(&smf(0, &[(0, on(69, 80)), (480, off(69))]), "division");
    let fast = smf(480, &[(0, tempo(1)), (0, on(69, 80)), (480, off(69))]);
    refused(&fast, "tempo 60000000 bpm");
    let no_tempo = smf(480, &[(0, tempo(0)), (0, on(69, 80)), (480, off(69))]);
    refused(&no_tempo, "0 microseconds per quarter note");
    // Hours of silence: a note after 2^27 ticks at 2 s per quarter.
    let silent = smf(
        1,
        &[
            (0, on(69, 80)),
            (1, off(69)),
            (0x0fff_ffff, on(71, 80)),
            (1, off(71)),
        ],
    );
    refused(&silent, "silence");
    // A delta time whose continuation bits never end.
    let corrupt = smf_raw(
        480,
        vec![
            0x00, 0x90, 69, 80, 0xff, 0xff, 0xff, 0xff, 0xff, 0x80, 69, 0, 0x00, 0xff, 0x2f, 0x00,
        ],
    );
    refused(&corrupt, "not a valid Standard MIDI File");
    // Truncated.
    let mut cut = waltz(true);
    cut.truncate(30);
    assert!(timeline_from_midi(&cut).is_err());
}

#[test]
fn out_of_range_notes_move_by_octaves_only_when_asked() {
    let low = smf(
        480,
        &[
            (0, on(43, 80)),
            (480, off(43)),
            (0, on(112, 80)),
            (480, off(112)),
        ],
    );
    let opts = MidiOptions {
        transpose_into_range: true,
        ..MidiOptions::default()
    };
    let score = score_from_midi(&low, &opts).unwrap();
    assert_eq!(
        score.notes.iter().map(|n| n.midi).collect::<Vec<_>>(),
        vec![55, 100]
    );
    assert_eq!(score.transposed, 2);
}

#[test]
fn file_errors_name_the_file() {
    let e = timeline_from_midi_file("/no/such.mid")
        .unwrap_err()
        .to_string();
    assert!(e.contains("/no/such.mid"), "{e}");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("empty.mid");
    std::fs::write(&path, smf(480, &[])).unwrap();
    let e = timeline_from_midi_file(&path).unwrap_err().to_string();
    assert!(
        e.starts_with(&path.display().to_string()) && e.contains("no notes"),
        "{e}"
    );
}

/// Eight eighths (bar 1), eight 32nds and a quarter (bar 2) at 120 bpm in 4/4, each note
/// starting `jitter(i)` ticks late and ending `gap` ticks before the next note starts.
fn run_file(gap: u32, jitter: impl Fn(usize) -> u32) -> Vec<u8> {
    let lengths = [[240u32; 8].as_slice(), &[60; 8], &[480]].concat();
    // (tick, event) in time order: note-offs before note-ons at the same tick.
    let mut at: Vec<(u32, u8, Vec<u8>)> = Vec::new();
    let mut slot = 0;
    for (i, len) in lengths.iter().enumerate() {
        let key = 67 + (i % 5) as u8;
        at.push((slot + jitter(i), 1, on(key, 80)));
        at.push((slot + len + jitter(i + 1) - gap, 0, off(key)));
        slot += len;
    }
    at.sort_by_key(|e| (e.0, e.1));
    let mut ev = vec![(0, tempo(500_000)), (0, time_sig(4, 2))];
    let mut now = 0;
    for (tick, _, bytes) in at {
        ev.push((tick - now, bytes));
        now = tick;
    }
    smf(480, &ev)
}

#[test]
fn notated_timing_gets_a_bow_per_note_but_for_ornaments() {
    use performance::midi::timing_is_notated;
    let rules = MidiBowing::default();
    let notated = score_from_midi(&run_file(0, |_| 0), &MidiOptions::default()).unwrap();
    assert!(timing_is_notated(&notated, &rules));
    let changes: Vec<bool> = (timeline_from_score_with(&notated, &rules).notes.iter())
        .map(|n| n.bow_change)
        .collect();
    // Every eighth takes a bow; the 32nds (0.0625 s) are slurred up to six; the quarter
    // takes a bow.
    let expected = [
        [true; 8].as_slice(),
        &[true, false, false, false, false, false, true, false],
        &[true],
    ]
    .concat();
    assert_eq!(changes, expected);
    // The rules for played timing would read the touching eighths as one slur.
    let played = MidiBowing {
        notated_below_share: 0.0,
        ..rules
    };
    let t = timeline_from_score_with(&notated, &played);
    assert!(!t.notes[1].bow_change);
    // Détaché gaps, or touching notes whose onsets are off the beat grid (played legato),
    // are not notated timing.
    let detached = score_from_midi(&run_file(20, |_| 0), &MidiOptions::default()).unwrap();
    assert!(!timing_is_notated(&detached, &rules));
    let jittered = run_file(0, |i| [0, 7, 3, 11, 5][i % 5]);
    let played_legato = score_from_midi(&jittered, &MidiOptions::default()).unwrap();
    assert_eq!(
        performance::midi::separated_share(&played_legato, 0.001),
        0.0
    );
    assert!(!timing_is_notated(&played_legato, &rules));
}
