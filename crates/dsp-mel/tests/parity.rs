//! Parity with librosa and scipy, against fixtures made by `scripts/make_fixtures.py`.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::PathBuf;

use dsp_mel::filters::{filtfilt, median_filter, Butterworth, EdgeMode};
use dsp_mel::{DbConfig, Hop, MelConfig, MelNorm, MelScale, MelSpectrogram};
use ndarray::{Array1, Array2};
use ndarray_npy::read_npy;
use serde_json::Value;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

fn signal(sr: u32) -> Vec<f32> {
    let a: Array1<f32> = read_npy(fixture(&format!("signal_{sr}.npy"))).unwrap();
    a.to_vec()
}

/// Worst relative error over bins within 80 dB of the reference maximum, and the worst dB
/// difference there.
fn compare(
    ours: &Array2<f32>,
    reference: &Array2<f64>,
    ours_db: &Array2<f32>,
    ref_db: &Array2<f64>,
) -> (f64, f64) {
    assert_eq!(ours.dim(), reference.dim());
    let max = reference.iter().cloned().fold(0.0, f64::max);
    let floor = max * 1e-8;
    let (mut rel, mut db) = (0.0f64, 0.0f64);
    for (idx, &r) in reference.indexed_iter() {
        if r >= floor {
            rel = rel.max((f64::from(ours[idx]) - r).abs() / r);
            db = db.max((f64::from(ours_db[idx]) - ref_db[idx]).abs());
        }
    }
    (rel, db)
}

fn mel30_parity(sr: u32) {
    let cfg = MelConfig::bowing().at_sample_rate(sr);
    let mel = MelSpectrogram::new(cfg).unwrap();
    let y = signal(sr);
    let ours = mel.compute(&y).unwrap();
    let ours_db = mel.compute_db(&y, &DbConfig::default()).unwrap();
    let reference: Array2<f64> = read_npy(fixture(&format!("mel30_{sr}_power.npy"))).unwrap();
    let ref_db: Array2<f64> = read_npy(fixture(&format!("mel30_{sr}_db.npy"))).unwrap();
    let (rel, db) = compare(&ours, &reference, &ours_db, &ref_db);
    println!("mel30 @ {sr} Hz: max relative error {rel:.2e}, max dB error {db:.2e}");
    assert!(rel <= 1e-4, "relative error {rel}");
    assert!(db <= 0.01, "dB error {db}");
}

#[test]
fn mel30_matches_librosa_at_22050() {
    mel30_parity(22_050);
}

#[test]
fn mel30_matches_librosa_at_44100() {
    mel30_parity(44_100);
}

/// The single-precision transform (beat-track's onset spectrogram) against the same
/// fixture, with the same tolerances as double precision.
#[test]
fn single_precision_mel30_stays_close_to_librosa() {
    let cfg = MelConfig::bowing();
    let mel = MelSpectrogram::<f32>::with_precision(cfg).unwrap();
    let y = signal(22_050);
    let ours = mel.compute(&y).unwrap();
    let ours_db = mel.compute_db(&y, &DbConfig::default()).unwrap();
    let reference: Array2<f64> = read_npy(fixture("mel30_22050_power.npy")).unwrap();
    let ref_db: Array2<f64> = read_npy(fixture("mel30_22050_db.npy")).unwrap();
    let (rel, db) = compare(&ours, &reference, &ours_db, &ref_db);
    println!("mel30 @ 22050 Hz in f32: max relative error {rel:.2e}, max dB error {db:.2e}");
    assert!(rel <= 1e-4, "relative error {rel}");
    assert!(db <= 0.01, "dB error {db}");
}

#[test]
fn htk_magnitude_mel_matches_librosa() {
    let cfg = MelConfig {
        sample_rate_hz: 22_050,
        n_fft: 1024,
        hop: Hop::Samples(256),
        n_mels: 40,
        fmin_hz: 100.0,
        fmax_hz: Some(8000.0),
        mel_scale: MelScale::Htk,
        norm: MelNorm::None,
        power: 1.0,
        ..MelConfig::default()
    };
    let mel = MelSpectrogram::new(cfg).unwrap();
    let y = signal(22_050);
    let ours = mel.compute(&y).unwrap();
    let ours_db = mel.compute_db(&y, &DbConfig::default()).unwrap();
    let reference: Array2<f64> = read_npy(fixture("mel_htk_22050_power.npy")).unwrap();
    let ref_db: Array2<f64> = read_npy(fixture("mel_htk_22050_db.npy")).unwrap();
    let (rel, db) = compare(&ours, &reference, &ours_db, &ref_db);
    println!("htk magnitude mel: max relative error {rel:.2e}, max dB error {db:.2e}");
    assert!(rel <= 1e-4 && db <= 0.01, "rel {rel} db {db}");
}

#[test]
fn emotion_mel_matches_pooled_librosa() {
    let mel = MelSpectrogram::new(MelConfig::emotion()).unwrap();
    let ours = mel.compute(&signal(22_050)).unwrap();
    let reference: Array2<f64> = read_npy(fixture("mel2_22050_power.npy")).unwrap();
    let (rel, _) = compare(&ours, &reference, &ours, &reference.mapv(|_| 0.0));
    println!("mel2 (pooled): max relative error {rel:.2e}");
    assert!(rel <= 1e-4, "relative error {rel}");
}

fn filters_json() -> Value {
    serde_json::from_str(&std::fs::read_to_string(fixture("filters.json")).unwrap()).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn max_rel(ours: &[f64], reference: &[f64]) -> f64 {
    assert_eq!(ours.len(), reference.len());
    ours.iter()
        .zip(reference)
        .map(|(o, r)| {
            if *r == 0.0 {
                o.abs()
            } else {
                ((o - r) / r).abs()
            }
        })
        .fold(0.0, f64::max)
}

#[test]
fn butterworth_matches_scipy() {
    let json = filters_json();
    let mut worst = 0.0f64;
    for case in json["butter"].as_array().unwrap() {
        let order = case["order"].as_u64().unwrap() as usize;
        let design = Butterworth::lowpass(
            order,
            case["cutoff"].as_f64().unwrap(),
            case["fs"].as_f64().unwrap(),
        )
        .unwrap();
        let tf = design.transfer_function();
        worst = worst.max(max_rel(&tf.b, &floats(&case["b"])));
        worst = worst.max(max_rel(&tf.a, &floats(&case["a"])));
        let sos: Vec<f64> = design
            .second_order_sections()
            .into_iter()
            .flatten()
            .collect();
        let reference: Vec<f64> = case["sos"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(floats)
            .collect();
        let e = max_rel(&sos, &reference);
        assert!(
            e <= 1e-9,
            "order {order} sos: {e:e}\nours {sos:?}\nscipy {reference:?}"
        );
        worst = worst.max(e);
    }
    println!("butter: max relative coefficient error {worst:.2e}");
    assert!(worst <= 1e-9);
}

#[test]
fn filtfilt_matches_scipy() {
    let json = filters_json();
    for case in json["filtfilt"].as_array().unwrap() {
        let y = filtfilt(
            &floats(&case["b"]),
            &floats(&case["a"]),
            &floats(&case["x"]),
        )
        .unwrap();
        let reference = floats(&case["y"]);
        let err = y
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        println!("filtfilt order {}: max abs error {err:.2e}", case["order"]);
        assert!(err <= 1e-6, "{err}");
    }
}

#[test]
fn median_filters_match_scipy_exactly() {
    let json = filters_json();
    for (key, edge) in [
        ("medfilt", EdgeMode::Zero),
        ("median_nearest", EdgeMode::Nearest),
    ] {
        for case in json[key].as_array().unwrap() {
            let k = case["k"].as_u64().unwrap() as usize;
            let y = median_filter(&floats(&case["x"]), k, edge).unwrap();
            assert_eq!(y, floats(&case["y"]), "{key} k={k}");
        }
    }
}
