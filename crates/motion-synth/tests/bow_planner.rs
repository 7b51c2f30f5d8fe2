//! The bow planner on crafted change sequences: always inside the bow, reversing exactly on
//! the change frames, following the original rule where it fits.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use motion_synth::bow::{plan_bow, plan_naive, BowPolicy};
use motion_synth::metrics::bow_range_violations;
use motion_synth::{BowDirection, BowPlan};

/// Change frames from stroke lengths.
fn changes(lengths: &[usize]) -> (Vec<usize>, usize) {
    let mut out = Vec::new();
    let mut t = 0;
    for &l in lengths {
        t += l;
        out.push(t);
    }
    let total = out.pop().unwrap_or(0);
    (out, total)
}

/// In range, and the position turns exactly at every change frame.
fn check(plan: &BowPlan, change_frames: &[usize]) {
    let pos = plan.positions();
    assert_eq!(bow_range_violations(pos), 0.0, "left the bow");
    assert_eq!(plan.change_frames(), change_frames);
    for w in plan.strokes().windows(2) {
        let (a, b) = (&w[0], &w[1]);
        assert_eq!(a.end_frame, b.start_frame);
        assert_eq!(b.direction, a.direction.reversed());
        assert_eq!(a.end_position, b.start_position);
        let c = b.start_frame;
        assert_eq!(
            pos[c], b.start_position as f32,
            "stroke starts where planned"
        );
        // The frame before moves the old way, the frame after the new way.
        if a.end_position != a.start_position && c >= 1 {
            assert!(
                (pos[c] - pos[c - 1]) * a.direction.sign() as f32 > 0.0,
                "no approach at {c}"
            );
        }
        if b.end_position != b.start_position && c + 1 < pos.len() {
            assert!(
                (pos[c + 1] - pos[c]) * b.direction.sign() as f32 > 0.0,
                "no reversal at {c}"
            );
        }
    }
}

#[test]
fn many_short_strokes() {
    let (ch, n) = changes(&[4; 200]);
    let plan = plan_bow(&ch, n, &[], &BowPolicy::default()).unwrap();
    check(&plan, &ch);
    // 4-frame strokes travel 4/28 of the bow, as the original rule says.
    for s in plan.strokes() {
        assert!((s.end_position - s.start_position).abs() > 0.1);
    }
}

#[test]
fn long_strokes_use_the_whole_bow() {
    let (ch, n) = changes(&[60, 45, 90, 30, 120]);
    let plan = plan_bow(&ch, n, &[], &BowPolicy::default()).unwrap();
    check(&plan, &ch);
    for s in plan.strokes() {
        assert!((s.end_position - s.start_position).abs() == 1.0, "{s:?}");
    }
    assert_eq!(plan.strokes()[0].direction, BowDirection::Down);
    assert_eq!(
        plan.strokes()[0].start_position,
        0.0,
        "first down-bow at the frog"
    );
}

#[test]
fn alternating_5_and_40_frames_stays_in_the_bow_where_the_naive_rule_drifts() {
    let lengths: Vec<usize> = (0..40).map(|i| if i % 2 == 0 { 40 } else { 5 }).collect();
    let (ch, n) = changes(&lengths);
    let naive = plan_naive(&ch, n, &BowPolicy::default()).unwrap();
    assert!(
        bow_range_violations(naive.positions()) > 0.3,
        "the literal rule drifts"
    );
    let plan = plan_bow(&ch, n, &[], &BowPolicy::default()).unwrap();
    check(&plan, &ch);
    // Bow is distributed: long strokes still travel far, short ones quickly.
    let long_mean: f64 = plan
        .strokes()
        .iter()
        .step_by(2)
        .map(|s| (s.end_position - s.start_position).abs())
        .sum::<f64>()
        / 20.0;
    assert!(long_mean > 0.2, "long strokes shrank to {long_mean}");
}

#[test]
fn irregular_mixture_and_single_frame_strokes() {
    let (ch, n) = changes(&[1, 1, 2, 50, 3, 3, 14, 15, 16, 1, 27, 28, 29, 7, 100, 2]);
    let plan = plan_bow(&ch, n, &[], &BowPolicy::default()).unwrap();
    check(&plan, &ch);
}

#[test]
fn the_speed_is_smooth_inside_a_stroke() {
    let (ch, n) = changes(&[56, 56]);
    let plan = plan_bow(&ch, n, &[], &BowPolicy::default()).unwrap();
    let pos = plan.positions();
    let v: Vec<f32> = pos.windows(2).map(|w| w[1] - w[0]).collect();
    // Inside the first stroke: speed changes by small steps (no jumps), peaks mid-stroke.
    let max_step = v[..55]
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0, f32::max);
    assert!(max_step < 0.006, "velocity jump {max_step}");
    assert!(v[27] > 2.0 * v[0], "eases in");
    assert!(v[55] > 0.0 && v[56] < 0.0, "reverses at the change");
}

#[test]
fn downbeats_get_down_bows_when_the_changes_allow() {
    // Strokes of 30 frames; downbeats every 60 frames starting at frame 30.
    let (ch, n) = changes(&[30; 8]);
    let downbeats: Vec<f64> = (0..4).map(|i| 30.0 + 60.0 * i as f64).collect();
    let plan = plan_bow(&ch, n, &downbeats, &BowPolicy::default()).unwrap();
    check(&plan, &ch);
    for s in plan.strokes() {
        if downbeats.contains(&(s.start_frame as f64)) {
            assert_eq!(s.direction, BowDirection::Down);
        }
    }
    assert_eq!(
        plan.strokes()[0].start_position,
        1.0,
        "an up-bow start begins at the tip"
    );
}

#[test]
fn given_directions_are_followed_and_a_retake_starts_again_at_the_frog() {
    use motion_synth::bow::plan_bow_directed;
    // Down, up, then a down-bow retaken (down again) after a long stroke.
    let (c, total) = changes(&[30, 30, 40, 30]);
    let dirs = [
        BowDirection::Down,
        BowDirection::Up,
        BowDirection::Down,
        BowDirection::Down,
    ];
    let plan = plan_bow_directed(
        &c,
        total,
        |f| dirs[c.iter().filter(|&&x| x <= f).count()],
        &BowPolicy::default(),
    )
    .unwrap();
    let got: Vec<BowDirection> = plan.strokes().iter().map(|s| s.direction).collect();
    assert_eq!(got, dirs);
    assert_eq!(bow_range_violations(plan.positions()), 0.0);
    let s = plan.strokes();
    // The retaken stroke does not start where the previous down-bow ended (near the tip).
    assert!(s[3].start_position < s[2].end_position, "{s:?}");
    assert!(s[3].end_position > s[3].start_position);
}
