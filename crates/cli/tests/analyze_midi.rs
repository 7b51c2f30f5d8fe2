//! `violin-skeleton analyze X.mid` and `generate X.mid --analysis-out`: the analysis.json
//! schema from a MIDI file, the fingering flags, and bad MIDI files refused with one line.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::Command;

use serde_json::Value;

fn cli() -> Command {
    Command::new(env!("CARGO_BIN_EXE_violin-skeleton"))
}

fn vlq(mut v: u32) -> Vec<u8> {
    let mut out = vec![(v & 0x7f) as u8];
    v >>= 7;
    while v > 0 {
        out.insert(0, 0x80 | (v & 0x7f) as u8);
        v >>= 7;
    }
    out
}

/// A format-0 file from (delta, event bytes).
fn smf(division: u16, events: &[(u32, Vec<u8>)]) -> Vec<u8> {
    let mut track = Vec::new();
    for (delta, bytes) in events {
        track.extend(vlq(*delta));
        track.extend(bytes);
    }
    track.extend([0x00, 0xff, 0x2f, 0x00]);
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

/// Quarter notes of `keys` at 120 bpm (each sounding 450 of its 480 ticks) with
/// `velocity(i)`, the note `lower.1` sounding under note `lower.0` (a double stop), and a 4/4
/// time signature when asked.
fn quarters(
    keys: &[u8],
    velocity: impl Fn(usize) -> u8,
    lower: (usize, u8),
    four_four: bool,
) -> Vec<u8> {
    let mut ev = vec![(0, vec![0xff, 0x51, 0x03, 0x07, 0xa1, 0x20])];
    if four_four {
        ev.push((0, vec![0xff, 0x58, 0x04, 4, 2, 24, 8]));
    }
    for (i, &k) in keys.iter().enumerate() {
        let chord = i == lower.0;
        ev.push((0, vec![0x90, k, velocity(i)]));
        if chord {
            ev.push((0, vec![0x90, lower.1, 70]));
        }
        ev.push((450, vec![0x80, k, 0]));
        if chord {
            ev.push((0, vec![0x80, lower.1, 0]));
        }
        ev.push((30, vec![0xff, 0x01, 0]));
    }
    smf(480, &ev)
}

/// 4/4 at 120 bpm: eight quarter notes (a scale G4..G5, the fourth one with a D4 double
/// stop below).
fn scale_file() -> Vec<u8> {
    let scale = [67u8, 69, 71, 72, 74, 76, 78, 79];
    quarters(&scale, |i| 70 + i as u8, (3, 62), true)
}

fn run(args: &[&str], input: &Path, out: &Path) -> std::process::Output {
    cli()
        .args(args)
        .arg(input)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap()
}

#[test]
fn a_midi_file_gives_the_analysis_schema() {
    let dir = tempfile::tempdir().unwrap();
    let mid = dir.path().join("scale.mid");
    std::fs::write(&mid, scale_file()).unwrap();
    let out = dir.path().join("a.json");
    let o = run(&["analyze"], &mid, &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(v["source"], "midi");
    assert_eq!(v["schema_version"], 3);
    // One stroke per bow change, with its direction and the string of its first note.
    let strokes = v["bow_strokes"].as_array().unwrap();
    assert_eq!(strokes.len(), v["bow_changes_s"].as_array().unwrap().len());
    for s in strokes {
        assert!(
            ["down", "up"].contains(&s["direction"].as_str().unwrap()),
            "{s}"
        );
        assert!((1..=4).contains(&s["string"].as_u64().unwrap()), "{s}");
        assert!(s["end_s"].as_f64().unwrap() >= s["start_s"].as_f64().unwrap());
    }
    let notes = v["notes"].as_array().unwrap();
    assert_eq!(notes.len(), 9); // the double stop is kept
    for n in notes {
        for key in [
            "onset_s", "offset_s", "midi", "velocity", "string", "position", "finger",
        ] {
            assert!(n.get(key).is_some(), "{key} missing in {n}");
        }
    }
    assert_eq!(notes[0]["velocity"], 70);
    let (top, low) = (&notes[3], &notes[4]);
    assert_eq!(
        (top["midi"].as_u64(), low["midi"].as_u64()),
        (Some(72), Some(62))
    );
    assert_eq!(
        top["string"].as_u64().unwrap() - low["string"].as_u64().unwrap(),
        1
    );
    assert_eq!(v["beats_s"].as_array().unwrap().len(), 8);
    assert_eq!(v["downbeats_s"][1], 2.0);
    assert_eq!(v["meter"]["beats_per_bar"], 4);
    assert_eq!(v["tempo_bpm"], 120.0);
    let changes = v["bow_changes_s"].as_array().unwrap().len();
    assert_eq!(v["bow_directions"].as_array().unwrap().len(), changes);
    assert_eq!(v["bow_directions"][0], "down");
    assert!(!v["arousal"]["values"].as_array().unwrap().is_empty());
    assert!(!v["f0"]["hz"].as_array().unwrap().is_empty());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("timing:"), "{stderr}");

    // generate --analysis-out writes the same analysis; the fingering flags apply.
    let motion = dir.path().join("m.json");
    let same = dir.path().join("b.json");
    let o = cli()
        .args(["generate"])
        .arg(&mid)
        .arg("-o")
        .arg(&motion)
        .arg("--analysis-out")
        .arg(&same)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let w: Value = serde_json::from_slice(&std::fs::read(&same).unwrap()).unwrap();
    assert_eq!(w["notes"], v["notes"]);
    let sul = dir.path().join("sul.json");
    let o = run(
        &["analyze", "--sul", "G", "--planner", "viterbi"],
        &mid,
        &sul,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: Value = serde_json::from_slice(&std::fs::read(&sul).unwrap()).unwrap();
    let on_g = s["notes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|n| n["string"] == 1)
        .count();
    assert!(on_g >= 7, "{s}");

    // `--fingering` names the same flag as `--planner`.
    let by_planner = dir.path().join("p.json");
    let by_fingering = dir.path().join("f.json");
    for (flag, out) in [("--planner", &by_planner), ("--fingering", &by_fingering)] {
        let o = run(&["analyze", flag, "greedy"], &mid, out);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let notes = |p: &Path| -> Value {
        serde_json::from_slice::<Value>(&std::fs::read(p).unwrap()).unwrap()["notes"].clone()
    };
    assert_eq!(notes(&by_planner), notes(&by_fingering));
    assert_ne!(notes(&by_planner), v["notes"]); // greedy is not the default planner
}

#[test]
fn bad_midi_files_are_refused_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let note = |k: u8| vec![(0, vec![0x90, k, 80]), (480, vec![0x80, k, 0])];
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("empty.mid", smf(480, &[]), "no notes"),
        (
            "drums.mid",
            smf(480, &[(0, vec![0x99, 38, 100]), (240, vec![0x89, 38, 0])]),
            "percussion",
        ),
        ("low.mid", smf(480, &note(43)), "--transpose-into-range"),
        ("div0.mid", smf(0, &note(69)), "division"),
        (
            "garbage.mid",
            b"MThd nonsense".to_vec(),
            "not a valid Standard MIDI File",
        ),
    ];
    for (name, bytes, reason) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        let o = run(&["analyze"], &path, &dir.path().join("x.json"));
        assert_eq!(o.status.code(), Some(1), "{name}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(name) && err.contains(reason), "{name}: {err}");
    }
    // With the flag, the low note moves up an octave.
    let low = dir.path().join("low.mid");
    let out = dir.path().join("low.json");
    let o = run(&["analyze", "--transpose-into-range"], &low, &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(v["notes"][0]["midi"], 55);
}

/// The sixth E5 over G4 at 1.0–1.5 s after D5, between plain notes (120 bpm).
fn sixth_file() -> Vec<u8> {
    quarters(&[71, 74, 76, 78], |_| 80, (2, 67), false)
}

#[test]
fn a_double_stop_is_fingered_in_reach_and_bowed_across_both_strings() {
    use violin_skeleton::motion_synth::{synthesize_detailed, SynthConfig};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sixth.mid");
    std::fs::write(&path, sixth_file()).unwrap();
    let perf = violin_skeleton::Pipeline::default()
        .performance_from_midi(&path)
        .unwrap();
    // The line keeps E5; G4 is the second voice, on the string next below, in reach.
    assert_eq!(perf.notes().len(), 4);
    let [g4] = perf.double_stops() else {
        panic!("{:?}", perf.double_stops())
    };
    let (e5, g4_place) = (perf.notes()[2].fingering.unwrap(), g4.fingering.unwrap());
    assert_eq!((g4.midi, g4.onset_s), (67, 1.0));
    assert_eq!(e5.string.number(), g4_place.string.number() + 1);
    assert!(g4_place.is_open() || e5.position.abs_diff(g4_place.position) <= 1);
    // The bow lies across both strings while they sound, on E5's alone before and after.
    let synth = synthesize_detailed(&perf, &SynthConfig::default()).unwrap();
    let across = f64::from(e5.string.number() + g4_place.string.number()) / 2.0 - 1.0;
    assert_eq!(synth.string_index[38], across); // 1.27 s
    let after = f64::from(perf.notes()[3].fingering.unwrap().string.number() - 1);
    assert_eq!(synth.string_index[55], after); // 1.83 s

    // G4's finger is down on its string beside E5's while they sound, and only then.
    let also = synth.fingers[38].also_down.expect("G4 stopped");
    assert_eq!(also.finger, g4_place.finger);
    assert_eq!(also.string + 1, g4_place.string.number());
    assert_eq!(synth.fingers[38].down.map(|d| d.finger), Some(e5.finger));
    assert!(synth.fingers[55].also_down.is_none());
}
