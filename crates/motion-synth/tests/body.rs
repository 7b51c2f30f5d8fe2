//! Body rules: smooth arousal, lean with arousal, head sway phased on downbeats.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use motion_synth::body::{body_track, BodyConfig};
use performance::{ArousalCurve, Performance};

fn perf(duration: f64, downbeats: Vec<f64>, arousal: Option<Vec<f32>>) -> Performance {
    let mut b = Performance::builder(duration)
        .note(0.0, duration, 69)
        .downbeats(downbeats);
    if let Some(v) = arousal {
        b = b.arousal(ArousalCurve::deam(v));
    }
    b.build().unwrap()
}

#[test]
fn arousal_is_interpolated_smoothly_without_overshoot() {
    let values = vec![-0.8, -0.2, 0.9, 0.1, 0.1, -1.0, 1.0, 0.3];
    let p = perf(4.0, vec![], Some(values.clone()));
    let t = body_track(&p, 30.0, 120, &BodyConfig::default());
    // Through the knots (every 15 frames) …
    for (i, v) in values.iter().enumerate() {
        assert!((t.arousal[i * 15] - f64::from(*v)).abs() < 1e-6);
    }
    // … within [-1, 1] and between neighbouring knots …
    for k in 0..values.len() - 1 {
        let (lo, hi) = (values[k].min(values[k + 1]), values[k].max(values[k + 1]));
        for f in k * 15..=(k + 1) * 15 {
            assert!(t.arousal[f] >= f64::from(lo) - 1e-9 && t.arousal[f] <= f64::from(hi) + 1e-9);
        }
    }
    // … with no kinks: sampled finely, the slope never jumps (a C¹ curve's one-sided
    // slopes agree; linear interpolation would jump by about 2.8 per second at knots).
    let fine = body_track(&p, 3000.0, 12_000, &BodyConfig::default());
    let max_jump = fine
        .arousal
        .windows(3)
        .map(|w| (w[2] - 2.0 * w[1] + w[0]).abs() * 3000.0)
        .fold(0.0, f64::max);
    assert!(max_jump < 0.1, "slope jump {max_jump} per second");
}

#[test]
fn torso_leans_back_as_arousal_rises_and_is_neutral_without_it() {
    let p = perf(
        10.0,
        vec![],
        Some((0..20).map(|i| -1.0 + i as f32 / 10.0).collect()),
    );
    let cfg = BodyConfig::default();
    let t = body_track(&p, 30.0, 300, &cfg);
    assert!(
        t.torso_pitch_rad[0] > t.torso_pitch_rad[299] + 4f64.to_radians(),
        "calm leans forward"
    );
    assert!(
        t.torso_pitch_rad.windows(2).all(|w| w[1] <= w[0] + 1e-12),
        "monotone with arousal"
    );
    let neutral = body_track(&perf(10.0, vec![], None), 30.0, 300, &cfg);
    assert!(neutral
        .torso_pitch_rad
        .iter()
        .all(|&v| (v - cfg.lean_forward_deg.to_radians()).abs() < 1e-12));
    assert!(neutral.arousal.iter().all(|&a| a == 0.0));
}

/// Frames where the head is furthest forward (local maxima of the nod).
fn forward_peaks(h: &[f64]) -> Vec<usize> {
    (1..h.len() - 1)
        .filter(|&i| h[i] > h[i - 1] && h[i] >= h[i + 1])
        .collect()
}

#[test]
fn head_is_forward_on_each_downbeat_and_back_between() {
    let downbeats = vec![0.5, 2.5, 4.3, 6.1, 8.0];
    let p = perf(10.0, downbeats.clone(), Some(vec![0.2; 20]));
    let t = body_track(&p, 30.0, 300, &BodyConfig::default());
    let peaks = forward_peaks(&t.head_pitch_rad);
    for d in &downbeats {
        let f = d * 30.0;
        assert!(
            peaks.iter().any(|&p| (p as f64 - f).abs() <= 1.0),
            "no forward peak at {d} s: {peaks:?}"
        );
    }
    // Forward peaks only on bar lines (the downbeats, and the bar repeated after the last
    // one), and the head is back (negative) between downbeats.
    for p in &peaks {
        assert!(
            t.bar_lines_s
                .iter()
                .any(|b| (b * 30.0 - *p as f64).abs() <= 1.0),
            "peak {p} off the bars"
        );
    }
    for w in downbeats.windows(2) {
        assert!(
            t.head_pitch_rad[((w[0] + w[1]) / 2.0 * 30.0) as usize] < 0.0,
            "not back mid-bar"
        );
    }
}

#[test]
fn excited_bars_sway_further_and_faster() {
    let downbeats: Vec<f64> = (0..5).map(|i| i as f64 * 2.0).collect();
    let mut arousal = vec![-0.9f32; 10];
    arousal.extend(vec![0.9f32; 10]);
    let p = perf(10.0, downbeats, Some(arousal));
    let t = body_track(&p, 30.0, 300, &BodyConfig::default());
    let range = |a: usize, b: usize| {
        let s = &t.head_pitch_rad[a..b];
        s.iter().cloned().fold(f64::MIN, f64::max) - s.iter().cloned().fold(f64::MAX, f64::min)
    };
    let accel = |a: usize, b: usize| {
        let s = &t.head_pitch_rad[a..b];
        s.windows(3)
            .map(|w| (w[2] - 2.0 * w[1] + w[0]).abs())
            .fold(0.0, f64::max)
    };
    assert!(
        range(240, 299) > 2.0 * range(0, 60),
        "extent grows with arousal"
    );
    assert!(
        accel(240, 299) > 3.0 * accel(0, 60),
        "head acceleration grows with arousal"
    );
}

#[test]
fn without_downbeats_the_head_sways_every_two_seconds() {
    let p = perf(9.0, vec![], None);
    let t = body_track(&p, 30.0, 270, &BodyConfig::default());
    let peaks = forward_peaks(&t.head_pitch_rad);
    assert_eq!(peaks, vec![60, 120, 180, 240]);
    assert_eq!(t.bar_lines_s, vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
}
