//! Every layer's gradient against central finite differences (f64 for precision), and the
//! custom ops' forward values against candle's reference ops.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use bowing_net::nn::{conv2d_nhwc, max_pool2x2_nhwc, store, weighted_cross_entropy};
use bowing_net::{BowingNet, Config};
use candle_core::{DType, Device, Tensor, Var};
use candle_nn::{VarBuilder, VarMap};
use corpus::rng::Rng;

fn random(shape: &[usize], seed: u64) -> Tensor {
    let mut rng = Rng::new(seed);
    let n: usize = shape.iter().product();
    let v: Vec<f32> = (0..n).map(|_| rng.uniform(-1.0, 1.0) as f32).collect();
    Tensor::from_vec(v, shape, &Device::Cpu).unwrap()
}

/// Checks d(sum(f(x) * proj))/dx against finite differences on up to `samples` elements.
fn check_grad(x0: &Tensor, f: &dyn Fn(&Tensor) -> Tensor, samples: usize, tol: f64) {
    check_grad_eps(x0, f, samples, tol, 1e-2);
}

/// [`check_grad`] with the finite-difference step `eps`.
fn check_grad_eps(x0: &Tensor, f: &dyn Fn(&Tensor) -> Tensor, samples: usize, tol: f64, eps: f32) {
    let x = Var::from_tensor(x0).unwrap();
    let y = f(x.as_tensor());
    let proj = random(y.dims(), 99);
    let loss = (y * &proj).unwrap().sum_all().unwrap();
    let grads = loss.backward().unwrap();
    let g = grads
        .get(x.as_tensor())
        .unwrap()
        .flatten_all()
        .unwrap()
        .to_vec1::<f32>()
        .unwrap();
    let base = x0.flatten_all().unwrap().to_vec1::<f32>().unwrap();
    let n = base.len();
    let step = (n / samples).max(1);
    let mut checked = 0;
    for i in (0..n).step_by(step) {
        let eval = |delta: f32| {
            let mut v = base.clone();
            v[i] += delta;
            let t = Tensor::from_vec(v, x0.dims(), &Device::Cpu).unwrap();
            let y = f(&t);
            f64::from(
                (y * &proj)
                    .unwrap()
                    .sum_all()
                    .unwrap()
                    .to_scalar::<f32>()
                    .unwrap(),
            )
        };
        let numeric = (eval(eps) - eval(-eps)) / (2.0 * f64::from(eps));
        let analytic = f64::from(g[i]);
        let err = (numeric - analytic).abs() / numeric.abs().max(analytic.abs()).max(1.0);
        assert!(
            err < tol,
            "element {i}: numeric {numeric}, analytic {analytic}"
        );
        checked += 1;
    }
    assert!(checked > 0);
}

#[test]
fn conv_matches_candle_forward() {
    let x = random(&[2, 9, 11, 3], 1);
    let w = random(&[4, 3, 5, 5], 2);
    let b = random(&[4], 3);
    for pad in [0usize, 2] {
        let ours = conv2d_nhwc(&x, &w, &b, (pad, pad)).unwrap();
        let theirs = x
            .permute((0, 3, 1, 2))
            .unwrap()
            .conv2d(&w, pad, 1, 1, 1)
            .unwrap()
            .broadcast_add(&b.reshape((1, 4, 1, 1)).unwrap())
            .unwrap()
            .permute((0, 2, 3, 1))
            .unwrap();
        let diff = (ours - theirs)
            .unwrap()
            .abs()
            .unwrap()
            .max_all()
            .unwrap()
            .to_scalar::<f32>()
            .unwrap();
        assert!(diff < 1e-4, "pad {pad}: max diff {diff}");
    }
}

#[test]
fn conv_gradients_are_exact() {
    let x = random(&[2, 7, 8, 2], 4);
    let w = random(&[3, 2, 3, 3], 5);
    let b = random(&[3], 6);
    for pad in [0usize, 1] {
        check_grad(
            &x,
            &|x| conv2d_nhwc(x, &w, &b, (pad, pad)).unwrap(),
            60,
            1e-2,
        );
        check_grad(
            &w,
            &|w| conv2d_nhwc(&x, w, &b, (pad, pad)).unwrap(),
            54,
            1e-2,
        );
        check_grad(
            &b,
            &|b| conv2d_nhwc(&x, &w, b, (pad, pad)).unwrap(),
            3,
            1e-2,
        );
    }
}

#[test]
fn max_pool_matches_candle_forward_and_has_exact_gradients_on_odd_sizes() {
    // Odd height and width (as the CNN's third pool sees): the last row/column is dropped.
    let x = separated(&[2, 7, 9, 3], 7);
    let ours = max_pool2x2_nhwc(&x).unwrap();
    assert_eq!(ours.dims(), &[2, 3, 4, 3]);
    let theirs = x
        .permute((0, 3, 1, 2))
        .unwrap()
        .max_pool2d(2)
        .unwrap()
        .permute((0, 2, 3, 1))
        .unwrap();
    let diff = (&ours - theirs)
        .unwrap()
        .abs()
        .unwrap()
        .max_all()
        .unwrap()
        .to_scalar::<f32>()
        .unwrap();
    assert_eq!(diff, 0.0);
    check_grad(&x, &|x| max_pool2x2_nhwc(x).unwrap(), 400, 1e-3);
    // The gradient of a dropped row is zero, and the total equals the sum of the upstream.
    let v = Var::from_tensor(&x).unwrap();
    let g = max_pool2x2_nhwc(v.as_tensor())
        .unwrap()
        .sum_all()
        .unwrap()
        .backward()
        .unwrap();
    let g = g.get(v.as_tensor()).unwrap();
    assert_eq!(
        g.narrow(1, 6, 1)
            .unwrap()
            .abs()
            .unwrap()
            .sum_all()
            .unwrap()
            .to_scalar::<f32>()
            .unwrap(),
        0.0
    );
    assert_eq!(
        g.sum_all().unwrap().to_scalar::<f32>().unwrap(),
        2.0 * 3.0 * 4.0 * 3.0
    );
}

#[test]
fn weighted_cross_entropy_gradient_is_exact() {
    let logits = random(&[6, 2], 8);
    let targets = Tensor::new(&[0u32, 1, 1, 0, 1, 0], &Device::Cpu).unwrap();
    let weights = Tensor::new(&[1.0f32, 3.0, 3.0, 1.0, 0.0, 1.0], &Device::Cpu).unwrap();
    check_grad(
        &logits,
        &|l| {
            weighted_cross_entropy(l, &targets, &weights)
                .unwrap()
                .reshape(1)
                .unwrap()
        },
        12,
        1e-2,
    );
}

#[test]
fn whole_network_gradients_are_exact() {
    let cfg = Config::default();
    let varmap = VarMap::new();
    let net = BowingNet::new(
        &cfg,
        VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu),
    )
    .unwrap();
    store::init_seeded(&varmap, 3, |n, d| {
        (!n.starts_with("norm."))
            .then(|| (6.0 / d.iter().skip(1).product::<usize>().max(1) as f64).sqrt())
    })
    .unwrap();
    let x = (random(&[2, 60, 128], 9) * 3.0).unwrap();
    // Gradient with respect to the input (all layers chained, dropout off).
    check_grad(&x, &|x| net.forward_t(x, false).unwrap(), 40, 2e-2);
    // And with respect to every parameter tensor (one value each).
    let logits = net.forward_t(&x, false).unwrap();
    let grads = logits.sum_all().unwrap().backward().unwrap();
    for (name, var) in store::trainable_vars(&varmap, |n| n.starts_with("norm.")) {
        let g = grads
            .get(var.as_tensor())
            .unwrap_or_else(|| panic!("no gradient for {name}"));
        assert_eq!(g.dims(), var.as_tensor().dims());
        let base = var
            .as_tensor()
            .flatten_all()
            .unwrap()
            .to_vec1::<f32>()
            .unwrap();
        let gv = g.flatten_all().unwrap().to_vec1::<f32>().unwrap();
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
            let s = net
                .forward_t(&x, false)
                .unwrap()
                .sum_all()
                .unwrap()
                .to_scalar::<f32>()
                .unwrap();
            f64::from(s)
        };
        let numeric = (eval(eps) - eval(-eps)) / (2.0 * f64::from(eps));
        var.set(&Tensor::from_vec(base.clone(), var.as_tensor().dims(), &Device::Cpu).unwrap())
            .unwrap();
        let analytic = f64::from(gv[i]);
        let err = (numeric - analytic).abs() / numeric.abs().max(analytic.abs()).max(1.0);
        assert!(
            err < 2e-2,
            "{name}[{i}]: numeric {numeric}, analytic {analytic}"
        );
    }
}

#[test]
fn phase_tree_gradients_are_exact() {
    let cfg = Config::default();
    let varmap = VarMap::new();
    let net = BowingNet::new(
        &cfg,
        VarBuilder::from_varmap(&varmap, DType::F32, &Device::Cpu),
    )
    .unwrap();
    store::init_seeded(&varmap, 4, |n, d| {
        (!n.starts_with("norm."))
            .then(|| (6.0 / d.iter().skip(1).product::<usize>().max(1) as f64).sqrt())
    })
    .unwrap();
    let x = (random(&[2, 60 + 16 + 7, 128], 10) * 3.0).unwrap();
    check_grad_eps(
        &x,
        &|x| net.sequence_logits(x, false).unwrap(),
        40,
        2e-2,
        1e-3,
    );
    let logits = net.sequence_logits(&x, false).unwrap();
    let proj = random(logits.dims(), 5);
    let grads = (logits * &proj)
        .unwrap()
        .sum_all()
        .unwrap()
        .backward()
        .unwrap();
    for (name, var) in store::trainable_vars(&varmap, |n| n.starts_with("norm.")) {
        let gv = grads
            .get(var.as_tensor())
            .unwrap()
            .flatten_all()
            .unwrap()
            .to_vec1::<f32>()
            .unwrap();
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
            let l = net.sequence_logits(&x, false).unwrap();
            f64::from(
                (l * &proj)
                    .unwrap()
                    .sum_all()
                    .unwrap()
                    .to_scalar::<f32>()
                    .unwrap(),
            )
        };
        let numeric = (eval(eps) - eval(-eps)) / (2.0 * f64::from(eps));
        var.set(&Tensor::from_vec(base.clone(), var.as_tensor().dims(), &Device::Cpu).unwrap())
            .unwrap();
        let analytic = f64::from(gv[i]);
        let err = (numeric - analytic).abs() / numeric.abs().max(analytic.abs()).max(1.0);
        assert!(
            err < 2e-2,
            "{name}[{i}]: numeric {numeric}, analytic {analytic}"
        );
    }
}

/// Distinct values 0.05 apart in shuffled order: no two inputs of a pool cell are within
/// the finite-difference step, so every difference quotient is a true derivative.
fn separated(shape: &[usize], seed: u64) -> Tensor {
    let n: usize = shape.iter().product();
    let mut v: Vec<f32> = (0..n).map(|i| (i as f32 - n as f32 / 2.0) * 0.05).collect();
    let mut rng = Rng::new(seed);
    for i in (1..n).rev() {
        v.swap(i, (rng.next_u64() % (i as u64 + 1)) as usize);
    }
    Tensor::from_vec(v, shape, &Device::Cpu).unwrap()
}

#[test]
fn pools_of_shared_inputs_concatenated_have_exact_gradients() {
    // The phase tree's pattern: two pool alignments of one tensor, stacked on the batch axis.
    let y = separated(&[2, 9, 6, 3], 21);
    check_grad(
        &y,
        &|y| {
            let even = max_pool2x2_nhwc(&y.narrow(1, 0, 8).unwrap()).unwrap();
            let odd = max_pool2x2_nhwc(&y.narrow(1, 1, 8).unwrap()).unwrap();
            Tensor::cat(&[&even, &odd], 0).unwrap()
        },
        324,
        1e-3,
    );
}
