//! Every layer's gradient (convolutions, batch norm in both modes, dense, GRU, maxout)
//! against central finite differences.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use bowing_net::nn::store;
use candle_core::{DType, Device, Tensor, Var};
use candle_nn::{VarBuilder, VarMap};
use corpus::rng::Rng;
use emotion_net::{Config, EmotionNet};

fn random(shape: &[usize], seed: u64, scale: f64) -> Tensor {
    let mut rng = Rng::new(seed);
    let n: usize = shape.iter().product();
    let v: Vec<f32> = (0..n).map(|_| rng.uniform(-scale, scale) as f32).collect();
    Tensor::from_vec(v, shape, &Device::Cpu).unwrap()
}

fn net(seed: u64) -> (VarMap, EmotionNet) {
    // Dropout off so the function is deterministic; the shapes are the SPEC's.
    let cfg = Config {
        conv_dropout: 0.0,
        dense_dropout: 0.0,
        gru_dropout: 0.0,
        ..Config::default()
    };
    let varmap = VarMap::new();
    let net = EmotionNet::new(
        &cfg,
        VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu),
    )
    .unwrap();
    store::init_seeded(&varmap, seed, |n, d| {
        if n.starts_with("norm.") || n.contains("running_") {
            None
        } else {
            Some((3.0 / d.iter().skip(1).product::<usize>().max(1) as f64).sqrt())
        }
    })
    .unwrap();
    (varmap, net)
}

fn check_params(varmap: &VarMap, f: &dyn Fn() -> f64, grads: &candle_core::backprop::GradStore) {
    for (name, var) in
        store::trainable_vars(varmap, |n| n.starts_with("norm.") || n.contains("running_"))
    {
        let g = grads
            .get(var.as_tensor())
            .unwrap_or_else(|| panic!("no gradient for {name}"));
        let gv = g.flatten_all().unwrap().to_vec1::<f32>().unwrap();
        let base = var
            .as_tensor()
            .flatten_all()
            .unwrap()
            .to_vec1::<f32>()
            .unwrap();
        let i = gv
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .unwrap()
            .0;
        let eps = 1e-3f32;
        let eval = |d: f32| {
            let mut v = base.clone();
            v[i] += d;
            var.set(&Tensor::from_vec(v, var.as_tensor().dims(), &Device::Cpu).unwrap())
                .unwrap();
            f()
        };
        let numeric = (eval(eps) - eval(-eps)) / (2.0 * f64::from(eps));
        var.set(&Tensor::from_vec(base.clone(), var.as_tensor().dims(), &Device::Cpu).unwrap())
            .unwrap();
        let analytic = f64::from(gv[i]);
        // Relative 3 %, plus an absolute allowance for f32 rounding of the loss (a conv bias
        // before a training-mode batch norm has an exact gradient of 0).
        let ok = (numeric - analytic).abs() <= 3e-2 * numeric.abs().max(analytic.abs()) + 2e-3;
        assert!(ok, "{name}[{i}]: numeric {numeric}, analytic {analytic}");
    }
}

#[test]
fn gradients_in_inference_and_training_mode_are_exact() {
    let (varmap, net) = net(3);
    let x = random(&[3, 20, 64], 4, 2.0);
    let proj = random(&[3, 20], 5, 1.0);
    for train in [false, true] {
        let loss = |x: &Tensor| {
            (net.forward_t(x, train).unwrap() * &proj)
                .unwrap()
                .sum_all()
                .unwrap()
        };
        let value = || f64::from(loss(&x).to_scalar::<f32>().unwrap());
        let xv = Var::from_tensor(&x).unwrap();
        let grads = loss(xv.as_tensor()).backward().unwrap();
        check_params(&varmap, &value, &grads);
        // Input gradient at a few positions.
        let gx = grads
            .get(xv.as_tensor())
            .unwrap()
            .flatten_all()
            .unwrap()
            .to_vec1::<f32>()
            .unwrap();
        let base = x.flatten_all().unwrap().to_vec1::<f32>().unwrap();
        let mut order: Vec<usize> = (0..gx.len()).collect();
        order.sort_by(|&a, &b| gx[b].abs().total_cmp(&gx[a].abs()));
        for &i in order.iter().take(4) {
            let at = |d: f32| {
                let mut v = base.clone();
                v[i] += d;
                f64::from(
                    loss(&Tensor::from_vec(v, x.dims(), &Device::Cpu).unwrap())
                        .to_scalar::<f32>()
                        .unwrap(),
                )
            };
            let numeric = (at(1e-2) - at(-1e-2)) / 2e-2;
            let err = (numeric - f64::from(gx[i])).abs() / numeric.abs().max(1e-2);
            assert!(
                err < 3e-2,
                "train {train} input {i}: numeric {numeric}, analytic {}",
                gx[i]
            );
        }
    }
}
