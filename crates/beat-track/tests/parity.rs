//! Parity with librosa 0.11 and mir_eval 0.8.2 (fixtures from
//! `scripts/make_mir_eval_fixtures.py`).
//!
//! Tolerances: onset strength within 1e-4 absolute (values peak near 18; measured 1.0e-5 for
//! the mean and 3.0e-5 for the median aggregation: float32 arithmetic in both),
//! mean absolute difference ≤ 1e-5;
//! onset_detect frames identical; tempo within 0.5 bpm; beat frames identical given
//! librosa's own envelope; beat F-measure within 1e-12 of mir_eval.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use beat_track::eval::{beat_prf, BEAT_TOLERANCE_S};
use beat_track::{estimate_tempo, onset_detect, track_beats, OnsetConfig, OnsetStrength, PeakPick};
use serde_json::Value;

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn frames(v: &Value) -> Vec<usize> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as usize)
        .collect()
}

/// The formula of `test_signal` in the fixture script.
fn test_signal(sr: usize, seconds: f64) -> Vec<f32> {
    let n = (sr as f64 * seconds) as usize;
    let mut y = vec![0.0f64; n];
    let mut k = 0usize;
    while 0.2 + 0.4 * (k as f64) < seconds - 0.4 {
        let start = 0.2 + 0.4 * k as f64;
        let f = 220.0 * 2f64.powf(((k * 5 % 7) as f64) / 12.0);
        let amp = if k.is_multiple_of(4) { 0.6 } else { 0.3 };
        for (i, v) in y.iter_mut().enumerate() {
            let t = i as f64 / sr as f64;
            if t >= start && t < start + 0.38 {
                let tt = t - start;
                let env = amp * (1.0 - (-tt / 0.01).exp()) * (-tt / 0.3).exp();
                let w = 2.0 * std::f64::consts::PI * f * tt;
                *v += env * (w.sin() + 0.5 * (2.0 * w).sin() + 0.25 * (3.0 * w).sin());
            }
        }
        k += 1;
    }
    y.into_iter().map(|v| v as f32).collect()
}

fn librosa() -> Value {
    serde_json::from_str(include_str!("fixtures/librosa_beats.json")).unwrap()
}

#[test]
fn onset_strength_matches_librosa() {
    let f = librosa();
    let y = test_signal(22_050, 12.0);
    let env = OnsetStrength::new(OnsetConfig {
        with_median: true,
        ..OnsetConfig::default()
    })
    .unwrap()
    .compute(&y)
    .unwrap();
    for (ours, key) in [
        (&env.mean, "onset_strength_mean"),
        (&env.median, "onset_strength_median"),
    ] {
        let theirs = floats(&f[key]);
        assert_eq!(ours.len(), theirs.len(), "{key}");
        let diffs: Vec<f64> = ours
            .iter()
            .zip(&theirs)
            .map(|(a, b)| (f64::from(*a) - b).abs())
            .collect();
        let max = diffs.iter().copied().fold(0.0, f64::max);
        let mean = diffs.iter().sum::<f64>() / diffs.len() as f64;
        println!("{key}: max |diff| {max:.2e}, mean {mean:.2e}");
        assert!(max <= 1e-4 && mean <= 1e-5, "{key}: max {max}, mean {mean}");
    }
    let onsets = onset_detect(&env.mean, &PeakPick::onset_defaults(22_050, 512));
    assert_eq!(onsets, frames(&f["onset_frames"]));
}

#[test]
fn tempo_and_beats_match_librosa_on_its_envelope() {
    let f = librosa();
    let env: Vec<f32> = floats(&f["onset_strength_median"])
        .iter()
        .map(|&v| v as f32)
        .collect();
    let bpm = estimate_tempo(&env, 22_050, 512, &Default::default()).unwrap();
    let theirs = f["tempo_bpm"].as_f64().unwrap();
    println!("tempo: ours {bpm:.3}, librosa {theirs:.3}");
    assert!((bpm - theirs).abs() < 0.5);
    let beats = track_beats(&env, theirs, 22_050.0 / 512.0, 100.0, true);
    assert_eq!(beats, frames(&f["beat_frames"]));
}

#[test]
fn beat_f_measure_equals_mir_eval() {
    let f: Value = serde_json::from_str(include_str!("fixtures/mir_eval.json")).unwrap();
    for case in f["beats"].as_array().unwrap() {
        let s = beat_prf(
            &floats(&case["reference_s"]),
            &floats(&case["estimated_s"]),
            BEAT_TOLERANCE_S,
        );
        let theirs = case["f_measure"].as_f64().unwrap();
        assert!(
            (s.f_measure - theirs).abs() < 1e-12,
            "{} vs mir_eval {theirs}",
            s.f_measure
        );
    }
}
