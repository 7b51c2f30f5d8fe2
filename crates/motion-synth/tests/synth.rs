//! Synthesis end to end: arms follow strings, shifts and the bow; tracks are complete.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use fingering::{Fingering, ViolinString};
use motion_synth::metrics::MotionReport;
use motion_synth::{synthesize_detailed, SynthConfig};
use performance::Performance;
use skeleton::{InstrumentPoint, Joint};

fn y3(m: &skeleton::Motion, f: usize, j: Joint) -> f32 {
    m.frames_3d().unwrap()[[f, j.index(), 1]]
}

#[test]
fn the_bow_arm_is_highest_on_g_and_lowest_on_e() {
    let strings = [
        ViolinString::G,
        ViolinString::D,
        ViolinString::A,
        ViolinString::E,
    ];
    let mut b = Performance::builder(4.0);
    for (i, s) in strings.into_iter().enumerate() {
        b = b.fingered_note(
            i as f64,
            i as f64 + 1.0,
            s.open_midi(),
            Fingering::open(s, 1),
        );
    }
    // One long stroke per note, so the bow is at the same place at mid-note.
    let perf = b.bow_changes(vec![1.0, 2.0, 3.0]).build().unwrap();
    let out = synthesize_detailed(&perf, &SynthConfig::default()).unwrap();
    let m = &out.motion;
    // Compare the elbows at the same bow position in the two down-bows (G and A) and
    // the two up-bows (D and E).
    assert!(y3(m, 15, Joint::RElbow) > y3(m, 75, Joint::RElbow) + 0.03);
    assert!(y3(m, 45, Joint::RElbow) > y3(m, 105, Joint::RElbow) + 0.03);
    assert!(
        (out.string_index[15] - 0.0).abs() < 1e-9 && (out.string_index[105] - 3.0).abs() < 1e-9
    );
}

#[test]
fn the_left_hand_shifts_just_before_the_note() {
    // A4 in first position, then A5 in 7th-ish position on the E string.
    let perf = Performance::builder(2.0)
        .fingered_note(0.0, 1.0, 71, Fingering::new(ViolinString::A, 1, 1))
        .fingered_note(1.0, 2.0, 88, Fingering::new(ViolinString::E, 7, 1))
        .build()
        .unwrap();
    let out = synthesize_detailed(&perf, &SynthConfig::default()).unwrap();
    let h = &out.hand_semitones;
    assert_eq!(
        h[25], 2.0,
        "still in first position 0.17 s before the shift"
    );
    assert!(h[28] > 2.0 && h[28] < 12.0, "gliding");
    assert_eq!(h[30], 12.0, "arrived on the onset");
    // The wrist moved towards the violin's body (back along the neck) by several cm.
    let lw = |f: usize| {
        let t = out.motion.frames_3d().unwrap();
        let s = out.motion.instrument_3d().unwrap();
        let scroll = InstrumentPoint::ALL
            .iter()
            .position(|p| *p == InstrumentPoint::ViolinScroll)
            .unwrap();
        (0..3)
            .map(|c| (t[[f, Joint::LWrist.index(), c]] - s[[f, scroll, c]]).powi(2))
            .sum::<f32>()
            .sqrt()
    };
    assert!(lw(40) > lw(10) + 0.05, "{} vs {}", lw(40), lw(10));
}

#[test]
fn every_track_is_there_and_the_bow_moves_with_the_strokes() {
    let perf = Performance::builder(3.0)
        .note(0.0, 1.5, 62)
        .note(1.5, 3.0, 66)
        .bow_changes(vec![1.5])
        .beats(vec![0.0, 0.75, 1.5, 2.25])
        .build()
        .unwrap();
    let out = synthesize_detailed(&perf, &SynthConfig::default()).unwrap();
    let m = &out.motion;
    assert_eq!(m.image_size(), Some((1280, 720)));
    assert_eq!(m.instrument().unwrap().dim(), (90, 4, 2));
    assert_eq!(m.instrument_3d().unwrap().dim(), (90, 4, 3));
    // 2-D: the head is above the neck, the left arm on the image's right.
    let p = m.frames();
    for f in [0, 45, 89] {
        assert!(p[[f, Joint::Nose.index(), 1]] < p[[f, Joint::Neck.index(), 1]]);
        assert!(p[[f, Joint::LShoulder.index(), 0]] > p[[f, Joint::RShoulder.index(), 0]]);
    }
    // Down-bow then up-bow: the frog travels away from the violin and comes back.
    let frog = |f: usize| m.instrument_3d().unwrap()[[f, 0, 0]];
    assert!(frog(44) < frog(0) - 0.3 && frog(89) > frog(44) + 0.3);
    let report = MotionReport::measure(&out, &perf);
    assert_eq!(report.bow_range_violations, 0.0);
    assert!(report.max_bone_length_cv < 1e-5);
    assert!(report.beat_alignment.unwrap() > 0.0);
    assert_eq!(report.unreached_frames, 0);
}
