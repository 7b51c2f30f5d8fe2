//! Property tests over random performances: the bow never leaves the bow, bones keep their
//! length, nothing is NaN, and synthesis is deterministic.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use motion_synth::{metrics, synthesize_detailed, SynthConfig};
use performance::Note;
use performance::{ArousalCurve, Performance};
use proptest::prelude::*;

/// A random but valid performance: notes with gaps, bow changes on some onsets plus a few
/// elsewhere, a beat grid, downbeats every 3 or 4 beats, maybe an arousal curve.
fn performance() -> impl Strategy<Value = Performance> {
    (
        prop::collection::vec((0.03f64..1.6, 0.0f64..0.3, 40u8..110, any::<bool>()), 1..60),
        prop::collection::vec(0.0f64..1.0, 0..8),
        0.3f64..0.9,
        3usize..5,
        prop::option::of(prop::collection::vec(-1.0f32..=1.0, 1..50)),
    )
        .prop_map(|(shape, extra, beat_s, meter, arousal)| {
            let mut notes = Vec::new();
            let mut changes = Vec::new();
            let mut t = 0.0;
            for (len, gap, midi, change) in shape {
                if change && t > 0.0 {
                    changes.push(t);
                }
                notes.push(Note::new(t, t + len, midi));
                t += len + gap;
            }
            let duration = t + 0.1;
            changes.extend(extra.iter().map(|u| u * duration));
            changes.retain(|c| *c > 0.0 && *c < duration);
            changes.sort_by(f64::total_cmp);
            changes.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
            let beats: Vec<f64> = (0..)
                .map(|i| i as f64 * beat_s)
                .take_while(|b| *b <= duration)
                .collect();
            let downbeats = beats.iter().copied().step_by(meter).collect();
            let mut b = Performance::builder(duration)
                .notes(notes)
                .bow_changes(changes)
                .beats(beats)
                .downbeats(downbeats);
            if let Some(values) = arousal {
                b = b.arousal(ArousalCurve::deam(values));
            }
            b.build().unwrap()
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn synthesis_is_in_range_rigid_finite_and_deterministic(perf in performance()) {
        let cfg = SynthConfig::default();
        let a = synthesize_detailed(&perf, &cfg).unwrap();
        prop_assert_eq!(a.motion.len(), perf.frame_count(30.0));
        prop_assert_eq!(metrics::bow_range_violations(a.bow.positions()), 0.0);
        prop_assert!(a.motion.max_bone_length_cv() < 0.005, "cv {}", a.motion.max_bone_length_cv());
        prop_assert_eq!(a.unreached_frames, 0);
        for track in [Some(a.motion.frames()), a.motion.frames_3d(), a.motion.instrument(), a.motion.instrument_3d()] {
            prop_assert!(track.unwrap().iter().all(|v| v.is_finite()));
        }
        let b = synthesize_detailed(&perf, &cfg).unwrap();
        prop_assert_eq!(&a.motion, &b.motion);
        prop_assert_eq!(a.bow.positions(), b.bow.positions());
    }

    #[test]
    fn strokes_reverse_on_every_kept_change(perf in performance()) {
        let out = synthesize_detailed(&perf, &SynthConfig::default()).unwrap();
        let pos = out.bow.positions();
        for s in out.bow.strokes() {
            let sign = s.direction.sign() as f32;
            // Within a stroke the bow moves one way only.
            for f in s.start_frame + 1..s.end_frame.min(pos.len()) {
                prop_assert!((pos[f] - pos[f - 1]) * sign >= -1e-6);
            }
        }
    }
}
