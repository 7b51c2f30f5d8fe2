//! The evaluation functions against mir_eval 0.8.2 on seeded random cases
//! (`scripts/make_mir_eval_fixtures.py`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use pitch_track::eval::{melody_scores, onset_prf};
use serde_json::Value;

fn fixture() -> Value {
    serde_json::from_str(include_str!("fixtures/mir_eval.json")).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn melody_scores_equal_mir_eval() {
    let f = fixture();
    for case in f["melody"].as_array().unwrap() {
        let r: Vec<f32> = floats(&case["reference_hz"])
            .iter()
            .map(|&x| x as f32)
            .collect();
        let e: Vec<f32> = floats(&case["estimated_hz"])
            .iter()
            .map(|&x| x as f32)
            .collect();
        let s = melody_scores(&r, &e, 50.0).unwrap();
        for (ours, key) in [
            (s.raw_pitch_accuracy, "raw_pitch_accuracy"),
            (s.voicing_recall, "voicing_recall"),
            (s.voicing_false_alarm, "voicing_false_alarm"),
            (s.overall_accuracy, "overall_accuracy"),
        ] {
            let theirs = case[key].as_f64().unwrap();
            assert!(
                (ours - theirs).abs() < 1e-12,
                "{key}: {ours} vs mir_eval {theirs}"
            );
        }
    }
}

#[test]
fn onset_scores_equal_mir_eval() {
    let f = fixture();
    for case in f["onsets"].as_array().unwrap() {
        let s = onset_prf(
            &floats(&case["reference_s"]),
            &floats(&case["estimated_s"]),
            0.05,
        );
        for (ours, key) in [
            (s.precision, "precision"),
            (s.recall, "recall"),
            (s.f_measure, "f_measure"),
        ] {
            let theirs = case[key].as_f64().unwrap();
            assert!(
                (ours - theirs).abs() < 1e-12,
                "{key}: {ours} vs mir_eval {theirs}"
            );
        }
    }
}
