//! Every layer's gradient (convolutions, linear and ReLU, batch norm in both modes, dense, GRU, maxout)
//! against central finite differences.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use candle_core::{Tensor, Var};
use candle_nn::VarMap;
use emotion_net::model::ConvActivation;
use emotion_net::{Config, EmotionNet};
use net_core::gradcheck::{check_input_gradient, check_parameter_gradients, uniform_tensor};
use net_core::vars;

fn random(shape: &[usize], seed: u64, scale: f64) -> Tensor {
    uniform_tensor(shape, seed, scale).unwrap()
}

fn net(seed: u64, conv_activation: ConvActivation) -> (VarMap, EmotionNet) {
    // Dropout off so the function is deterministic; the shapes are the SPEC's.
    let cfg = Config {
        conv_activation,
        conv_dropout: 0.0,
        dense_dropout: 0.0,
        gru_dropout: 0.0,
        ..Config::default()
    };
    common::seeded_net(
        &cfg,
        seed,
        &common::Keep {
            containing: &[],
            zero_biases: false,
        },
    )
}

#[test]
fn gradients_in_inference_and_training_mode_are_exact() {
    for activation in [ConvActivation::Linear, ConvActivation::Relu] {
        check_gradients(activation);
    }
}

fn check_gradients(activation: ConvActivation) {
    let (varmap, net) = net(3, activation);
    let x = random(&[3, 20, 64], 4, 2.0);
    let proj = random(&[3, 20], 5, 1.0);
    for train in [false, true] {
        let loss = |x: &Tensor| {
            (net.forward_t(x, train).unwrap() * &proj)
                .unwrap()
                .sum_all()
                .unwrap()
        };
        let value = || Ok(f64::from(loss(&x).to_scalar::<f32>()?));
        let xv = Var::from_tensor(&x).unwrap();
        let grads = loss(xv.as_tensor()).backward().unwrap();
        let params = vars::trainable_vars(&varmap, |n| {
            n.starts_with("norm.") || n.contains("running_")
        });
        // Relative 3 %, plus an absolute allowance for f32 rounding of the loss (a conv bias
        // before a training-mode batch norm has an exact gradient of 0). With ReLUs some
        // units cross their kink inside the finite-difference step (a shared parameter such
        // as a batch-norm shift moves thousands of them), so the central difference is only
        // close: 10 %.
        let rel_tol = match activation {
            ConvActivation::Linear => 3e-2,
            ConvActivation::Relu => 1e-1,
        };
        check_parameter_gradients(&params, &value, &grads, 1e-3, rel_tol, 2e-3)
            .unwrap_or_else(|e| panic!("{activation:?}, train {train}: {e}"));
        let checked = check_input_gradient(&x, &|x| Ok(loss(x)), 12, rel_tol, 1e-2)
            .unwrap_or_else(|e| panic!("{activation:?}, train {train}: {e}"));
        assert_eq!(checked, 12);
    }
}
