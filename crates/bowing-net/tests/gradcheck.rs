//! Every layer's gradient against central finite differences (f64 for precision), and the
//! custom ops' forward values against candle's reference ops.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use bowing_net::model::WeightInit;
use bowing_net::{BowingNet, Config};
use candle_core::{Device, Tensor, Var};
use candle_nn::VarMap;
use net_core::gradcheck::{check_input_gradient, check_parameter_gradients, uniform_tensor};
use net_core::nn::{
    conv2d_nhwc, conv2d_relu_nhwc, conv2d_relu_pool_phases_nhwc, max_pool2x2_nhwc,
    pool_phases_nhwc, weighted_cross_entropy,
};
use net_core::rng::Rng;
use net_core::vars;

fn random(shape: &[usize], seed: u64) -> Tensor {
    uniform_tensor(shape, seed, 1.0).unwrap()
}

/// Checks the input gradient of `f` on up to `samples` elements (finite-difference step 1e-2).
fn check_grad(x0: &Tensor, f: &dyn Fn(&Tensor) -> Tensor, samples: usize, tol: f64) {
    check_grad_eps(x0, f, samples, tol, 1e-2);
}

/// [`check_grad`] with the finite-difference step `eps`.
fn check_grad_eps(x0: &Tensor, f: &dyn Fn(&Tensor) -> Tensor, samples: usize, tol: f64, eps: f32) {
    let checked = check_input_gradient(x0, &|x| Ok(f(x)), samples, tol, eps).unwrap();
    assert!(checked > 0);
}

fn max_abs_diff(a: &Tensor, b: &Tensor) -> f32 {
    (a - b)
        .unwrap()
        .abs()
        .unwrap()
        .max_all()
        .unwrap()
        .to_scalar::<f32>()
        .unwrap()
}

/// A network of the SPEC's shape with seeded random weights.
fn random_net(seed: u64) -> (VarMap, BowingNet) {
    BowingNet::seeded(&Config::default(), WeightInit::HeUniform, seed).unwrap()
}

/// Every forward path of the op: 4 output channels (im2col + GEMM), 8 and 16 unpadded (the
/// direct kernel on CPUs with AVX2 + FMA: whole blocks of positions, an overlapping last
/// block, rows narrower than a block), padded (GEMM), one input channel (the CNN's first
/// layer).
#[test]
fn conv_matches_candle_forward() {
    let shapes = [
        (3, 4, 11),
        (3, 8, 23),
        (1, 16, 14),
        (16, 16, 17),
        (2, 8, 9),
        (2, 16, 7),
        // The bowing CNN's rows (128, 62 and 29 mel bands), which the direct kernel
        // covers with blocks of 6, 6 and 13 positions, and one covered by blocks of 12.
        (1, 16, 128),
        (16, 16, 62),
        (16, 8, 29),
        (4, 8, 28),
    ];
    for (seed, (cin, cout, width)) in shapes.into_iter().enumerate() {
        let seed = seed as u64 * 3;
        let x = random(&[2, 9, width, cin], seed + 1);
        let w = random(&[cout, cin, 5, 5], seed + 2);
        let b = random(&[cout], seed + 3);
        for pad in [0usize, 2] {
            let ours = conv2d_nhwc(&x, &w, &b, (pad, pad)).unwrap();
            let theirs = x
                .permute((0, 3, 1, 2))
                .unwrap()
                .conv2d(&w, pad, 1, 1, 1)
                .unwrap()
                .broadcast_add(&b.reshape((1, cout, 1, 1)).unwrap())
                .unwrap()
                .permute((0, 2, 3, 1))
                .unwrap();
            let diff = max_abs_diff(&ours, &theirs);
            assert!(diff < 1e-4, "{cin}→{cout}, pad {pad}: max diff {diff}");
            let fused = conv2d_relu_nhwc(&x, &w, &b, (pad, pad)).unwrap();
            let diff = max_abs_diff(&fused, &theirs.relu().unwrap());
            assert!(
                diff < 1e-4,
                "{cin}→{cout} + ReLU, pad {pad}: max diff {diff}"
            );
        }
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
    let (varmap, net) = random_net(3);
    let x = (random(&[2, 60, 128], 9) * 3.0).unwrap();
    // Gradient with respect to the input (all layers chained, dropout off).
    check_grad(&x, &|x| net.forward_t(x, false).unwrap(), 40, 2e-2);
    // And with respect to every parameter tensor (one value each); the input is a plain
    // tensor here, so the first convolution skips its input gradient.
    let loss = || {
        let s = net
            .forward_t(&x, false)
            .unwrap()
            .sum_all()?
            .to_scalar::<f32>()?;
        Ok(f64::from(s))
    };
    let grads = net
        .forward_t(&x, false)
        .unwrap()
        .sum_all()
        .unwrap()
        .backward()
        .unwrap();
    let params = vars::trainable_vars(&varmap, |n| n.starts_with("norm."));
    assert!(grads.get(&x).is_none(), "the data needs no gradient");
    check_parameter_gradients(&params, &loss, &grads, 1e-3, 2e-2, 2e-2).unwrap();
}

#[test]
fn phase_tree_gradients_are_exact() {
    let (varmap, net) = random_net(4);
    let x = (random(&[2, 60 + 16 + 7, 128], 10) * 3.0).unwrap();
    check_grad_eps(
        &x,
        &|x| net.sequence_logits(x, false).unwrap(),
        40,
        2e-2,
        1e-3,
    );
    let proj = random(net.sequence_logits(&x, false).unwrap().dims(), 5);
    let loss = || {
        let s = (net.sequence_logits(&x, false).unwrap() * &proj)?
            .sum_all()?
            .to_scalar::<f32>()?;
        Ok(f64::from(s))
    };
    let grads = (net.sequence_logits(&x, false).unwrap() * &proj)
        .unwrap()
        .sum_all()
        .unwrap()
        .backward()
        .unwrap();
    let params = vars::trainable_vars(&varmap, |n| n.starts_with("norm."));
    check_parameter_gradients(&params, &loss, &grads, 1e-3, 2e-2, 2e-2).unwrap();
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
fn fused_conv_relu_equals_conv_then_relu_with_exact_gradients() {
    let x = random(&[2, 7, 8, 3], 31);
    let w = random(&[4, 3, 3, 3], 32);
    let b = random(&[4], 33);
    for pad in [0usize, 1] {
        let fused = conv2d_relu_nhwc(&x, &w, &b, (pad, pad)).unwrap();
        let reference = conv2d_nhwc(&x, &w, &b, (pad, pad)).unwrap().relu().unwrap();
        assert!(max_abs_diff(&fused, &reference) < 1e-6);
        // Gradients equal those of conv (checked against finite differences above) → relu
        // (candle's); finite differences themselves would straddle the kink at 0.
        let (xv, wv, bv) = (
            Var::from_tensor(&x).unwrap(),
            Var::from_tensor(&w).unwrap(),
            Var::from_tensor(&b).unwrap(),
        );
        let proj = random(fused.dims(), 34);
        let grads = |y: Tensor| (y * &proj).unwrap().sum_all().unwrap().backward().unwrap();
        let (xt, wt, bt) = (xv.as_tensor(), wv.as_tensor(), bv.as_tensor());
        let g1 = grads(conv2d_relu_nhwc(xt, wt, bt, (pad, pad)).unwrap());
        let g2 = grads(conv2d_nhwc(xt, wt, bt, (pad, pad)).unwrap().relu().unwrap());
        for t in [xt, wt, bt] {
            assert!(max_abs_diff(g1.get(t).unwrap(), g2.get(t).unwrap()) < 1e-5);
        }
    }
}

#[test]
fn conv_skips_the_input_gradient_only_when_the_input_needs_none() {
    let x = random(&[1, 6, 6, 2], 34);
    let w = Var::from_tensor(&random(&[2, 2, 3, 3], 35)).unwrap();
    let b = Var::from_tensor(&random(&[2], 36)).unwrap();
    let grads = conv2d_nhwc(&x, w.as_tensor(), b.as_tensor(), (1, 1))
        .unwrap()
        .sum_all()
        .unwrap()
        .backward()
        .unwrap();
    assert!(grads.get(&x).is_none());
    assert!(grads.get(w.as_tensor()).is_some() && grads.get(b.as_tensor()).is_some());
    let xv = Var::from_tensor(&x).unwrap();
    let grads = conv2d_nhwc(xv.as_tensor(), w.as_tensor(), b.as_tensor(), (1, 1))
        .unwrap()
        .sum_all()
        .unwrap()
        .backward()
        .unwrap();
    assert_eq!(grads.get(xv.as_tensor()).unwrap().dims(), &[1, 6, 6, 2]);
}

#[test]
fn phase_pool_equals_two_pools_concatenated_with_exact_gradients() {
    // 69 and 70 rows: more than one task of output rows, with a ragged last task.
    for h in [9usize, 10, 69, 70] {
        let y = separated(&[2, h, 7, 3], 37 + h as u64);
        let k = (h - 1) / 2;
        let reference = Tensor::cat(
            &[
                &max_pool2x2_nhwc(&y.narrow(1, 0, 2 * k).unwrap()).unwrap(),
                &max_pool2x2_nhwc(&y.narrow(1, 1, 2 * k).unwrap()).unwrap(),
            ],
            0,
        )
        .unwrap();
        let fused = pool_phases_nhwc(&y).unwrap();
        assert_eq!(fused.dims(), &[4, k, 3, 3]);
        assert_eq!(max_abs_diff(&fused, &reference), 0.0);
        if h < 20 {
            check_grad(&y, &|y| pool_phases_nhwc(y).unwrap(), 400, 1e-3);
        }
    }
}

/// The fused inference op equals a convolution + ReLU then the phase pool, bit for bit, on
/// the bowing CNN's three stages (direct kernel), on 4 channels (the two ops' fallback) and
/// on rows too short for a block; it has no backward pass.
#[test]
fn fused_conv_pool_equals_the_two_ops() {
    for (seed, (b, h, w, cin, cout)) in [
        (2, 75, 128, 1, 16),
        (2, 35, 62, 16, 16),
        (4, 16, 29, 16, 8),
        (1, 12, 9, 3, 4),
        (1, 10, 7, 2, 8),
    ]
    .into_iter()
    .enumerate()
    {
        let seed = 50 + 3 * seed as u64;
        let x = random(&[b, h, w, cin], seed);
        let k = random(&[cout, cin, 5, 5], seed + 1);
        let bias = random(&[cout], seed + 2);
        let fused = conv2d_relu_pool_phases_nhwc(&x, &k, &bias).unwrap();
        let two = pool_phases_nhwc(&conv2d_relu_nhwc(&x, &k, &bias, (0, 0)).unwrap()).unwrap();
        assert_eq!(fused.dims(), two.dims());
        assert_eq!(
            max_abs_diff(&fused, &two),
            0.0,
            "{b}×{h}×{w}×{cin} → {cout}"
        );
    }
    let x = candle_core::Var::from_tensor(&random(&[1, 9, 9, 1], 3)).unwrap();
    let y =
        conv2d_relu_pool_phases_nhwc(x.as_tensor(), &random(&[8, 1, 5, 5], 4), &random(&[8], 5))
            .unwrap();
    assert!(y.sum_all().unwrap().backward().unwrap().get(&x).is_none());
}
