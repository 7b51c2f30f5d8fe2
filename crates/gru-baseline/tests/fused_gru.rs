#![allow(clippy::unwrap_used, clippy::expect_used)]
//! The fused GRU layer against candle's step-by-step `rnn::GRU`: same weights, same outputs
//! (forward) and same gradients (our hand-written BPTT against candle's autograd).

use candle_core::{DType, Device, Tensor, Var};
use candle_nn::rnn::{GRUConfig, GRUState, RNN};
use candle_nn::{VarBuilder, VarMap};
use gru_baseline::FusedGru;
use net_core::rng::Rng;

fn random(shape: &[usize], rng: &mut Rng, scale: f64) -> Tensor {
    let n: usize = shape.iter().product();
    let data: Vec<f32> = (0..n).map(|_| (rng.normal() * scale) as f32).collect();
    Tensor::from_vec(data, shape, &Device::Cpu).unwrap()
}

/// A VarMap with random weights AND biases (non-zero biases test their placement).
fn vars(in_dim: usize, hidden: usize, seed: u64) -> VarMap {
    let mut rng = Rng::new(seed);
    let map = VarMap::new();
    let entries = [
        ("g.weight_ih_l0", vec![3 * hidden, in_dim]),
        ("g.weight_hh_l0", vec![3 * hidden, hidden]),
        ("g.bias_ih_l0", vec![3 * hidden]),
        ("g.bias_hh_l0", vec![3 * hidden]),
    ];
    let mut data = map.data().lock().unwrap();
    for (name, shape) in entries {
        let t = random(&shape, &mut rng, 0.4);
        data.insert(name.to_string(), Var::from_tensor(&t).unwrap());
    }
    drop(data);
    map
}

fn candle_reference(gru: &candle_nn::rnn::GRU, x: &Tensor, h0: Option<&Tensor>) -> Tensor {
    let (batch, steps, _) = x.dims3().unwrap();
    let mut state = match h0 {
        Some(h) => GRUState { h: h.clone() },
        None => gru.zero_state(batch).unwrap(),
    };
    let mut outs = Vec::new();
    for t in 0..steps {
        let xt = x.narrow(1, t, 1).unwrap().squeeze(1).unwrap();
        state = gru.step(&xt, &state).unwrap();
        outs.push(state.h.clone());
    }
    Tensor::stack(&outs, 1).unwrap()
}

fn max_abs_diff(a: &Tensor, b: &Tensor) -> f32 {
    assert_eq!(a.dims(), b.dims());
    (a - b)
        .unwrap()
        .abs()
        .unwrap()
        .flatten_all()
        .unwrap()
        .max(0)
        .unwrap()
        .to_scalar::<f32>()
        .unwrap()
}

#[test]
fn forward_equals_candle_gru() {
    for (in_dim, hidden, steps, batch, seed) in [
        (6, 5, 9, 3, 1),
        (128, 64, 40, 4, 2),
        (1, 1, 1, 1, 3),
        (9, 20, 7, 13, 4),
    ] {
        let map = vars(in_dim, hidden, seed);
        let vb = VarBuilder::from_varmap(&map, DType::F32, &Device::Cpu);
        let fused = FusedGru::new(in_dim, hidden, vb.pp("g")).unwrap();
        let reference =
            candle_nn::rnn::gru(in_dim, hidden, GRUConfig::default(), vb.pp("g")).unwrap();
        let mut rng = Rng::new(seed + 100);
        let x = random(&[batch, steps, in_dim], &mut rng, 1.0);
        let ours = fused.forward(&x, None).unwrap();
        let theirs = candle_reference(&reference, &x, None);
        let d = max_abs_diff(&ours, &theirs);
        assert!(
            d < 1e-5,
            "zero state, in {in_dim} H {hidden}: max |diff| {d}"
        );
        let h0 = random(&[batch, hidden], &mut rng, 0.5);
        let ours = fused.forward(&x, Some(&h0)).unwrap();
        let theirs = candle_reference(&reference, &x, Some(&h0));
        let d = max_abs_diff(&ours, &theirs);
        assert!(
            d < 1e-5,
            "given state, in {in_dim} H {hidden}: max |diff| {d}"
        );
    }
}

#[test]
fn gradients_equal_candle_autograd() {
    let (in_dim, hidden, steps, batch) = (7, 6, 12, 9);
    let map = vars(in_dim, hidden, 11);
    let vb = VarBuilder::from_varmap(&map, DType::F32, &Device::Cpu);
    let fused = FusedGru::new(in_dim, hidden, vb.pp("g")).unwrap();
    let reference = candle_nn::rnn::gru(in_dim, hidden, GRUConfig::default(), vb.pp("g")).unwrap();
    let mut rng = Rng::new(12);
    let x = Var::from_tensor(&random(&[batch, steps, in_dim], &mut rng, 1.0)).unwrap();
    let h0 = random(&[batch, hidden], &mut rng, 0.5);
    let probe = random(&[batch, steps, hidden], &mut rng, 1.0);

    let loss_ours = (fused.forward(x.as_tensor(), Some(&h0)).unwrap() * &probe)
        .unwrap()
        .sum_all()
        .unwrap();
    let loss_theirs = (candle_reference(&reference, x.as_tensor(), Some(&h0)) * &probe)
        .unwrap()
        .sum_all()
        .unwrap();
    let a = loss_ours.to_scalar::<f32>().unwrap();
    let b = loss_theirs.to_scalar::<f32>().unwrap();
    assert!((a - b).abs() < 1e-4, "losses {a} vs {b}");
    let g_ours = loss_ours.backward().unwrap();
    let g_theirs = loss_theirs.backward().unwrap();
    let mut checked = 0;
    let data = map.data().lock().unwrap();
    for (name, var) in data.iter() {
        let go = g_ours.get(var.as_tensor()).expect("our gradient");
        let gt = g_theirs.get(var.as_tensor()).expect("candle gradient");
        let d = max_abs_diff(go, gt);
        assert!(d < 1e-4, "{name}: max |grad diff| {d}");
        checked += 1;
    }
    assert_eq!(checked, 4);
    let d = max_abs_diff(
        g_ours.get(x.as_tensor()).unwrap(),
        g_theirs.get(x.as_tensor()).unwrap(),
    );
    assert!(d < 1e-4, "input gradient: max |diff| {d}");
}

#[test]
fn wrong_shapes_are_typed_errors() {
    let map = vars(4, 3, 5);
    let vb = VarBuilder::from_varmap(&map, DType::F32, &Device::Cpu);
    let fused = FusedGru::new(4, 3, vb.pp("g")).unwrap();
    let x = Tensor::zeros((2, 5, 6), DType::F32, &Device::Cpu).unwrap();
    assert!(matches!(
        fused.forward(&x, None),
        Err(gru_baseline::GruError::Shape { .. })
    ));
    let x = Tensor::zeros((2, 5, 4), DType::F32, &Device::Cpu).unwrap();
    let h0 = Tensor::zeros((3, 3), DType::F32, &Device::Cpu).unwrap();
    assert!(matches!(
        fused.forward(&x, Some(&h0)),
        Err(gru_baseline::GruError::Shape { .. })
    ));
    let empty = Tensor::zeros((2, 0, 4), DType::F32, &Device::Cpu).unwrap();
    assert!(matches!(
        fused.forward(&empty, None),
        Err(gru_baseline::GruError::Empty(_))
    ));
}
