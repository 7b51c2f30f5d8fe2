#![allow(clippy::unwrap_used, clippy::expect_used)]
//! Weights files: save/load round trips (f32 exact, f16 close) and clear typed errors for
//! every kind of unusable file.

use std::collections::HashMap;
use std::path::Path;

use candle_core::{DType, Device, Tensor};
use gru_baseline::{
    Config, GruBaseline, GruError, MelStats, StorageDtype, TargetSpace, TrainingRecord,
};

fn small() -> GruBaseline {
    let cfg = Config {
        hidden: vec![8, 12, 8],
        ..Config::default()
    };
    let vars = GruBaseline::init_vars(&cfg, 5).unwrap();
    let mut net = GruBaseline::new(
        &cfg,
        candle_nn::VarBuilder::from_varmap(&vars, DType::F32, &Device::Cpu),
    )
    .unwrap();
    let stats = MelStats {
        mean: (0..128).map(|i| -40.0 + i as f32 * 0.1).collect(),
        std: (0..128).map(|i| 5.0 + i as f32 * 0.01).collect(),
    };
    let target = TargetSpace {
        center_px: [600.0, 350.0],
        torso_px: 210.0,
        image_size: Some((1280, 720)),
        coord_mean: (0..20).map(|i| i as f32 * 0.01 - 0.1).collect(),
        coord_std: (0..20).map(|i| 0.02 + i as f32 * 0.005).collect(),
    };
    net.set_normalization(stats, target).unwrap();
    net
}

fn mel() -> ndarray::Array2<f32> {
    ndarray::Array2::from_shape_fn((45, 128), |(t, b)| -50.0 + ((t * 7 + b * 3) % 40) as f32)
}

/// Rewrites a valid file with `edit` applied to its metadata and tensors.
fn rewrite(
    bytes: &[u8],
    edit: impl FnOnce(&mut HashMap<String, String>, &mut HashMap<String, Tensor>),
) -> Vec<u8> {
    let (_, header) = safetensors::SafeTensors::read_metadata(bytes).unwrap();
    let mut meta = header.metadata().clone().unwrap();
    let mut tensors = candle_core::safetensors::load_buffer(bytes, &Device::Cpu).unwrap();
    edit(&mut meta, &mut tensors);
    let mut list: Vec<(String, Tensor)> = tensors.into_iter().collect();
    list.sort_by(|a, b| a.0.cmp(&b.0));
    safetensors::serialize(list.iter().map(|(n, t)| (n.as_str(), t)), Some(meta)).unwrap()
}

fn load_err(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    match GruBaseline::load(&path) {
        Err(e @ GruError::Weights { .. }) => {
            let text = e.to_string();
            assert!(text.contains(name), "the error names the file: {text}");
            text
        }
        other => panic!("{name}: expected a weights error, got {other:?}"),
    }
}

#[test]
fn round_trip_f32_is_exact_and_f16_is_close() {
    let dir = tempfile::tempdir().unwrap();
    let net = small();
    let record = TrainingRecord {
        command: "violin-skeleton train gru".into(),
        seed: 4,
        epochs: 3,
        ..TrainingRecord::default()
    };
    let p32 = dir.path().join("w32.safetensors");
    net.save(&p32, StorageDtype::F32, Some(&record)).unwrap();
    let (back, rec) = GruBaseline::load_with_record(&p32).unwrap();
    assert_eq!(rec.as_ref(), Some(&record));
    assert_eq!(back.config(), net.config());
    assert_eq!(back.mel_stats(), net.mel_stats());
    assert_eq!(back.target_space(), net.target_space());
    let a = net.predict_normalized(mel().view()).unwrap();
    let b = back.predict_normalized(mel().view()).unwrap();
    assert_eq!(a, b);

    let p16 = dir.path().join("w16.safetensors");
    net.save(&p16, StorageDtype::F16, None).unwrap();
    assert!(std::fs::metadata(&p16).unwrap().len() < std::fs::metadata(&p32).unwrap().len());
    let (half, rec) = GruBaseline::load_with_record(&p16).unwrap();
    assert!(rec.is_none());
    let c = half.predict_normalized(mel().view()).unwrap();
    let d = (&a - &c).mapv(f32::abs).iter().cloned().fold(0.0, f32::max);
    assert!(d > 0.0 && d < 5e-3, "f16 max diff {d}");
}

#[test]
fn unusable_files_are_typed_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let good = small().to_bytes(StorageDtype::F32, None).unwrap();

    let missing = GruBaseline::load(dir.path().join("nope.safetensors")).unwrap_err();
    assert!(missing.to_string().contains("not found"), "{missing}");
    let e = load_err(
        dir.path(),
        "garbage.safetensors",
        b"hello, not a tensor file",
    );
    assert!(e.contains("not a safetensors"), "{e}");
    let e = load_err(dir.path(), "empty.safetensors", b"");
    assert!(e.contains("not a safetensors"), "{e}");
    let e = load_err(dir.path(), "truncated.safetensors", &good[..good.len() / 2]);
    assert!(
        e.contains("truncated") || e.contains("not a safetensors"),
        "{e}"
    );

    let other = rewrite(&good, |m, _| {
        m.insert("format".into(), "bowing-net".into());
    });
    let e = load_err(dir.path(), "other.safetensors", &other);
    assert!(e.contains("not a Method 1"), "{e}");
    let newer = rewrite(&good, |m, _| {
        m.insert("version".into(), "99".into());
    });
    let e = load_err(dir.path(), "newer.safetensors", &newer);
    assert!(e.contains("version 99"), "{e}");
    let reshaped = rewrite(&good, |_, t| {
        t.insert(
            "gru1.weight_hh_l0".into(),
            Tensor::zeros((36, 10), DType::F32, &Device::Cpu).unwrap(),
        );
    });
    let e = load_err(dir.path(), "reshaped.safetensors", &reshaped);
    assert!(
        e.contains("gru1.weight_hh_l0") && e.contains("shape"),
        "{e}"
    );
    let lacking = rewrite(&good, |_, t| {
        t.remove("head.bias");
    });
    let e = load_err(dir.path(), "lacking.safetensors", &lacking);
    assert!(e.contains("head.bias") && e.contains("missing"), "{e}");
    let extra = rewrite(&good, |_, t| {
        t.insert(
            "gru3.weight_ih_l0".into(),
            Tensor::zeros(3, DType::F32, &Device::Cpu).unwrap(),
        );
    });
    let e = load_err(dir.path(), "extra.safetensors", &extra);
    assert!(e.contains("unexpected tensor"), "{e}");
    let nan = rewrite(&good, |_, t| {
        t.insert(
            "head.bias".into(),
            Tensor::full(f32::NAN, 20, &Device::Cpu).unwrap(),
        );
    });
    let e = load_err(dir.path(), "nan.safetensors", &nan);
    assert!(e.contains("NaN"), "{e}");
    let bad_config = rewrite(&good, |m, _| {
        m.insert("config".into(), "{\"n_mels\": 128}".into());
    });
    let e = load_err(dir.path(), "config.safetensors", &bad_config);
    assert!(e.contains("config"), "{e}");
    let bad_stats = rewrite(&good, |m, _| {
        m.insert(
            "mel_stats".into(),
            "{\"mean\": [0.0], \"std\": [1.0]}".into(),
        );
    });
    let e = load_err(dir.path(), "stats.safetensors", &bad_stats);
    assert!(e.contains("normalisation"), "{e}");
}

#[test]
fn the_shipped_weights_load_with_their_record() {
    let net = GruBaseline::pretrained().unwrap();
    assert_eq!(net.config(), &Config::default());
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("weights/gru_baseline.safetensors");
    let (same, record) = GruBaseline::load_with_record(&file).unwrap();
    assert_eq!(same.mel_stats(), net.mel_stats());
    let record = record.expect("the shipped weights carry their training record");
    assert!(record.weighted_loss, "{record:?}");
    assert!(
        record.train_frames >= 60 * 60 * 30,
        "trained on >= 60 min: {record:?}"
    );
    assert!(std::fs::metadata(&file).unwrap().len() < 10_000_000);
    assert_eq!(net.target_space().image_size, Some((1280, 720)));
    let out = net.predict_mel(mel().view()).unwrap();
    assert_eq!(out.len(), 45);
    let (cx, cy) = out.mean_xy();
    assert!(
        (cx - 640.0).abs() < 120.0 && (cy - 360.0).abs() < 120.0,
        "{cx} {cy}"
    );
}
