//! Weights files (round trip and every rejection), variables, Adam's checkpointable state,
//! checkpoints and schedules.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::HashMap;
use std::path::Path;

use candle_core::{DType, Device, Tensor};
use candle_nn::{Init, VarBuilder, VarMap};
use net_core::file::{self, decode, encode, metadata};
use net_core::{
    checkpoint_path, load_checkpoint, resume_from_checkpoint, save_checkpoint, vars, Adam,
    AdamConfig, LrSchedule, TrainState,
};

/// The demo network's variables, all zero but `norm.mean` (`norm`).
fn blank_varmap(norm: f64) -> VarMap {
    let varmap = VarMap::new();
    let vb = VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu);
    vb.get_with_hints((3, 2), "dense.weight", Init::Const(0.0))
        .unwrap();
    vb.get_with_hints(3, "dense.bias", Init::Const(0.0))
        .unwrap();
    vb.get_with_hints(2, "norm.mean", Init::Const(norm))
        .unwrap();
    varmap
}

fn demo_varmap() -> VarMap {
    let varmap = blank_varmap(5.0);
    vars::init_seeded(&varmap, 7, |n, d| {
        (!n.starts_with("norm.")).then(|| vars::glorot_bound(d))
    })
    .unwrap();
    varmap
}

fn demo_bytes(varmap: &VarMap) -> Vec<u8> {
    let meta = metadata("demo-net", 3, &[("config", "{\"units\":3}".to_string())]);
    encode(&vars::var_tensors(varmap), meta).unwrap()
}

#[test]
fn weights_round_trip_with_metadata_and_checks() {
    let varmap = demo_varmap();
    let path = Path::new("demo.safetensors");
    let f = decode(&demo_bytes(&varmap), path).unwrap();
    f.check_format(path, "demo-net", 3).unwrap();
    assert_eq!(f.meta("config", path).unwrap(), "{\"units\":3}");
    let cfg: HashMap<String, usize> = f.meta_json("config", path).unwrap();
    assert_eq!(cfg["units"], 3);
    let expected = vars::var_shapes(&varmap);
    let taken = f.take_expected(path, &expected).unwrap();
    assert_eq!(taken.len(), 3);
    // Loading into a fresh map restores every value.
    let fresh = blank_varmap(0.0);
    vars::load_into(&fresh, &f.tensors, path).unwrap();
    assert_eq!(
        vars::var_tensors(&fresh)[0]
            .1
            .flatten_all()
            .unwrap()
            .to_vec1::<f32>()
            .unwrap(),
        vars::var_tensors(&varmap)[0]
            .1
            .flatten_all()
            .unwrap()
            .to_vec1::<f32>()
            .unwrap()
    );
}

#[test]
fn bad_weights_are_rejected_naming_the_file_and_the_problem() {
    let varmap = demo_varmap();
    let bytes = demo_bytes(&varmap);
    let path = Path::new("w.safetensors");
    let err = |r: Result<file::TensorFile, net_core::StoreError>| r.unwrap_err().to_string();
    // Empty and truncated.
    let e = err(decode(&[], path));
    assert!(
        e.contains("w.safetensors") && e.contains("truncated"),
        "{e}"
    );
    let e = err(decode(&bytes[..bytes.len() - 7], path));
    assert!(e.contains("truncated"), "{e}");
    // Wrong network, wrong version, missing metadata.
    let f = decode(&bytes, path).unwrap();
    let e = f
        .check_format(path, "other-net", 3)
        .unwrap_err()
        .to_string();
    assert!(e.contains("\"demo-net\"") && e.contains("other-net"), "{e}");
    let e = f.check_format(path, "demo-net", 4).unwrap_err().to_string();
    assert!(e.contains("version 3") && e.contains("retrain"), "{e}");
    let e = f.meta("decoder", path).unwrap_err().to_string();
    assert!(e.contains("\"decoder\""), "{e}");
    let e = f
        .meta_json::<Vec<u8>>("config", path)
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad \"config\""), "{e}");
    // Wrong shape, missing tensor.
    let e = f
        .check_shapes(path, &[("dense.weight".into(), vec![2, 3])])
        .unwrap_err()
        .to_string();
    assert!(e.contains("dense.weight") && e.contains("[3, 2]"), "{e}");
    let e = f
        .check_shapes(path, &[("dense2.weight".into(), vec![1])])
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing"), "{e}");
    // Non-finite values.
    let nan = Tensor::new(&[1.0f32, f32::NAN], &Device::Cpu).unwrap();
    let b = encode(&[("x".into(), nan)], metadata("demo-net", 3, &[])).unwrap();
    let e = err(decode(&b, path));
    assert!(e.contains("NaN"), "{e}");
    // A missing file.
    let e = err(file::read(Path::new("/nonexistent/none.safetensors")));
    assert!(e.contains("none.safetensors"), "{e}");
}

#[test]
fn adam_state_and_checkpoints_resume_exactly() {
    let varmap = demo_varmap();
    let params = vars::trainable_vars(&varmap, |n| n.starts_with("norm."));
    assert_eq!(params.len(), 2);
    let mut adam = Adam::new(params.clone(), AdamConfig::default()).unwrap();
    let x = Tensor::new(&[[1.0f32, -2.0]], &Device::Cpu).unwrap();
    let loss = |p: &[(String, candle_core::Var)]| {
        let w = p[1].1.as_tensor();
        x.matmul(&w.t().unwrap())
            .unwrap()
            .sqr()
            .unwrap()
            .sum_all()
            .unwrap()
    };
    for _ in 0..3 {
        adam.backward_step(&loss(&params)).unwrap();
    }
    assert_eq!(adam.steps(), 3);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("w.safetensors");
    let ckpt = checkpoint_path(&out);
    let mut state = TrainState::new("cfg".to_string(), -1.0);
    assert!(state.end_epoch(0, 0.25, 0.5));
    save_checkpoint(
        &ckpt,
        "demo-ckpt",
        1,
        vars::var_tensors(&varmap),
        &adam,
        &state,
    )
    .unwrap();
    let (f, back): (_, TrainState<String>) = load_checkpoint(&ckpt, "demo-ckpt", 1).unwrap();
    assert_eq!(back, state);
    let mut again = Adam::new(params.clone(), AdamConfig::default()).unwrap();
    again.load_state(&f.tensors).unwrap();
    assert_eq!(again.steps(), 3);
    for ((_, a), (_, b)) in adam
        .state()
        .unwrap()
        .iter()
        .zip(again.state().unwrap().iter())
    {
        assert_eq!(
            a.flatten_all().unwrap().to_vec1::<f32>().unwrap(),
            b.flatten_all().unwrap().to_vec1::<f32>().unwrap()
        );
    }
    // Wrong format, and no checkpoint at all.
    let e = load_checkpoint::<TrainState<String>>(&ckpt, "other-ckpt", 1)
        .unwrap_err()
        .to_string();
    assert!(e.contains("other-ckpt"), "{e}");
    let e = load_checkpoint::<TrainState<String>>(
        &dir.path().join("no.ckpt.safetensors"),
        "demo-ckpt",
        1,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("no.ckpt.safetensors") && e.contains("resume"),
        "{e}"
    );
    // A checkpoint missing the optimiser's tensors is refused.
    let mut no_moments = f.tensors.clone();
    no_moments.retain(|k, _| !k.starts_with("adam."));
    let e = again.load_state(&no_moments).unwrap_err().to_string();
    assert!(e.contains("optimizer"), "{e}");

    // Resuming in one call: the variables, the moments and the state come back; a
    // checkpoint of another network shape is refused, naming the file.
    let fresh = blank_varmap(0.0);
    let fresh_params = vars::trainable_vars(&fresh, |n| n.starts_with("norm."));
    let mut resumed = Adam::new(fresh_params, AdamConfig::default()).unwrap();
    let st = resume_from_checkpoint(
        &ckpt,
        "demo-ckpt",
        1,
        &"cfg".to_string(),
        &fresh,
        &mut resumed,
    )
    .unwrap();
    assert_eq!(st, state);
    assert_eq!(resumed.steps(), 3);
    let values = |m: &VarMap| -> Vec<Vec<f32>> {
        vars::var_tensors(m)
            .iter()
            .map(|(_, t)| t.flatten_all().unwrap().to_vec1::<f32>().unwrap())
            .collect()
    };
    assert_eq!(values(&fresh), values(&varmap));
    let e = resume_from_checkpoint(
        &ckpt,
        "demo-ckpt",
        1,
        &"other".to_string(),
        &fresh,
        &mut resumed,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("w.ckpt.safetensors") && e.contains("shape"),
        "{e}"
    );
}

#[test]
fn schedules_warm_up_then_decay_to_the_final_rate() {
    let s = LrSchedule::WarmupCosine {
        warmup_fraction: 0.1,
        final_fraction: 0.05,
    };
    let rates: Vec<f64> = (0..1000).map(|i| s.rate(1.0, i, 100, 10)).collect();
    let peak = rates.iter().cloned().fold(0.0, f64::max);
    assert!((peak - 1.0).abs() < 1e-9);
    assert!(rates[..100].windows(2).all(|w| w[1] >= w[0]));
    assert!(rates[100..].windows(2).all(|w| w[1] <= w[0] + 1e-12));
    assert!((rates[999] - 0.05).abs() < 1e-9);
    let json = serde_json::to_string(&s).unwrap();
    assert!(json.contains("warmup_cosine"), "{json}");
    assert_eq!(serde_json::from_str::<LrSchedule>(&json).unwrap(), s);
}

#[test]
fn band_statistics_ignore_extra_bands_and_floor_the_deviation() {
    let a = ndarray::Array2::from_shape_fn((4, 3), |(t, b)| (t * b) as f32);
    let (mean, std) = net_core::band_statistics([a.view()], 2);
    assert_eq!(mean, vec![0.0, 1.5]);
    assert_eq!(std[0], 1e-3);
    assert!((std[1] - 1.118_034).abs() < 1e-5);
    let (mean, _) = net_core::band_statistics(std::iter::empty(), 2);
    assert_eq!(mean, vec![0.0, 0.0]);
}

#[test]
fn the_same_weights_and_metadata_give_the_same_bytes() {
    let t = Tensor::from_vec(vec![1f32, 2.0, 3.0], 3, &Device::Cpu).unwrap();
    let meta: HashMap<String, String> = (0..16)
        .map(|k| (format!("key{k}"), k.to_string()))
        .collect();
    let a = encode(&[("w".into(), t.clone())], meta.clone()).unwrap();
    // A map built in another order (and with another hasher state) gives the same file.
    let rebuilt: HashMap<String, String> = (0..16)
        .rev()
        .map(|k| (format!("key{k}"), k.to_string()))
        .collect();
    assert_eq!(rebuilt, meta);
    let b = encode(&[("w".into(), t)], rebuilt).unwrap();
    assert_eq!(a, b);
    let parsed = decode(&a, Path::new("x")).unwrap();
    assert_eq!(parsed.metadata.get("key7").map(String::as_str), Some("7"));
    assert_eq!(u64::from_le_bytes(a[..8].try_into().unwrap()) % 8, 0);
    // Bytes that are no safetensors file pass through unchanged.
    assert_eq!(file::canonical_header(b"abc".to_vec()), b"abc".to_vec());
}
