//! The whole performer (issue #25): bow and fingertips on the strings, rigid bones, moving
//! fingers, everything inside an OpenPose canvas.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use motion_synth::metrics::MotionReport;
use motion_synth::{synthesize_detailed, SynthConfig};
use performance::{ArousalCurve, Performance};
use skeleton::{canvas::bounds_px, Canvas, Finger, PerformerPart};

/// A minute of a melody over the whole range: scales, leaps, held notes, string crossings.
fn performance() -> Performance {
    let pattern = [
        55u8, 59, 62, 67, 71, 74, 79, 83, 86, 81, 76, 72, 69, 64, 60, 57, 62, 66, 69, 74, 78, 81,
        88, 93,
    ];
    let mut b = Performance::builder(60.0);
    let (mut t, mut i, mut changes, mut beats) = (0.0, 0usize, Vec::new(), Vec::new());
    while t < 59.0 {
        let len = [0.25, 0.5, 0.25, 1.2, 0.4][i % 5];
        b = b.note(t, t + len * 0.95, pattern[i % pattern.len()]);
        changes.push(t);
        t += len;
        i += 1;
    }
    let mut bt = 0.0;
    while bt < 60.0 {
        beats.push(bt);
        bt += 0.5;
    }
    b.bow_changes(changes.into_iter().skip(1).collect())
        .downbeats(beats.iter().step_by(4).copied().collect())
        .beats(beats)
        .arousal(ArousalCurve::deam(
            (0..120).map(|k| ((k as f32) * 0.1).sin() * 0.8).collect(),
        ))
        .build()
        .unwrap()
}

#[test]
fn bow_and_fingers_touch_their_strings_and_bones_stay_rigid() {
    let perf = performance();
    let out = synthesize_detailed(&perf, &SynthConfig::default()).unwrap();
    let r = MotionReport::measure(&out, &perf);
    eprintln!("{}", serde_json::to_string(&r).unwrap());
    assert!(r.bow_string_contact.unwrap() >= 0.95, "{r:?}");
    assert!(r.fingertip_string_contact.unwrap() >= 0.95, "{r:?}");
    assert!(r.performer_bone_length_cv.unwrap() < 1e-4, "{r:?}");
    assert!(r.max_bone_length_cv < 1e-4);
    assert_eq!(r.unreached_frames, 0);

    // Fingers move relative to the wrist.
    let p = out.motion.performer().unwrap();
    let hand = p.track_3d(PerformerPart::LeftHand).unwrap();
    let tip = Finger::Middle.tip();
    let rel: Vec<f32> = (0..out.motion.len())
        .map(|f| hand[[f, tip, 1]] - hand[[f, 0, 1]])
        .collect();
    let (lo, hi) = rel
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    assert!(
        hi - lo > 0.005,
        "middle finger moves {} m relative to the wrist",
        hi - lo
    );

    // One scale for the clip: everything inside the canvas, with margins.
    let fitted = out.motion.fitted_to_canvas(Canvas::default(), 0.05);
    let [x0, y0, x1, y1] = bounds_px(&fitted).unwrap();
    assert!(
        x0 >= 0.0 && y0 >= 0.0 && x1 <= 1280.0 && y1 <= 720.0,
        "{x0} {y0} {x1} {y1}"
    );
}
