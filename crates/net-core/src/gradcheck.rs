//! Gradient checks against central finite differences, for the networks' tests: autograd
//! gradients of custom ops and whole networks must match what the function itself does.
//!
//! Both checks return `Err(message)` naming the first element that disagrees, so a test
//! can `assert!(check.is_ok(), …)` or unwrap it.
//!
//! ```
//! use candle_core::{Device, Tensor};
//! use net_core::gradcheck::{check_input_gradient, uniform_tensor};
//! let x = uniform_tensor(&[3, 4], 1, 1.0)?;
//! let checked = check_input_gradient(&x, &|x| x.sqr(), 12, 1e-2, 1e-2)
//!     .map_err(candle_core::Error::Msg)?;
//! assert_eq!(checked, 12);
//! # Ok::<(), candle_core::Error>(())
//! ```

use crate::rng::Rng;
use candle_core::backprop::GradStore;
use candle_core::{Device, Tensor, Var};

/// Values uniform in `±scale` from `seed`, shaped `shape`.
pub fn uniform_tensor(shape: &[usize], seed: u64, scale: f64) -> candle_core::Result<Tensor> {
    let mut rng = Rng::new(seed);
    let n: usize = shape.iter().product();
    let v: Vec<f32> = (0..n).map(|_| rng.uniform(-scale, scale) as f32).collect();
    Tensor::from_vec(v, shape, &Device::Cpu)
}

fn msg(e: candle_core::Error) -> String {
    e.to_string()
}

/// `|numeric − analytic| ≤ rel_tol·max(|numeric|, |analytic|, 1)`.
fn close(numeric: f64, analytic: f64, rel_tol: f64) -> bool {
    (numeric - analytic).abs() <= rel_tol * numeric.abs().max(analytic.abs()).max(1.0)
}

/// Checks d(Σ f(x) ⊙ P)/dx (`P` a fixed random projection) against central differences with
/// step `eps` on about `samples` evenly spread elements of `x0`; returns how many were
/// checked.
pub fn check_input_gradient(
    x0: &Tensor,
    f: &dyn Fn(&Tensor) -> candle_core::Result<Tensor>,
    samples: usize,
    rel_tol: f64,
    eps: f32,
) -> Result<usize, String> {
    let x = Var::from_tensor(x0).map_err(msg)?;
    let y = f(x.as_tensor()).map_err(msg)?;
    let proj = uniform_tensor(y.dims(), 99, 1.0).map_err(msg)?;
    let loss = (y * &proj).and_then(|t| t.sum_all()).map_err(msg)?;
    let grads = loss.backward().map_err(msg)?;
    let g = grads
        .get(x.as_tensor())
        .ok_or("the input got no gradient")?
        .flatten_all()
        .and_then(|t| t.to_vec1::<f32>())
        .map_err(msg)?;
    let base = x0
        .flatten_all()
        .and_then(|t| t.to_vec1::<f32>())
        .map_err(msg)?;
    let eval = |i: usize, delta: f32| -> Result<f64, String> {
        let mut v = base.clone();
        v[i] += delta;
        let t = Tensor::from_vec(v, x0.dims(), &Device::Cpu).map_err(msg)?;
        let s = (f(&t).map_err(msg)? * &proj)
            .and_then(|t| t.sum_all())
            .and_then(|t| t.to_scalar::<f32>())
            .map_err(msg)?;
        Ok(f64::from(s))
    };
    let step = (base.len() / samples.max(1)).max(1);
    let mut checked = 0;
    for i in (0..base.len()).step_by(step) {
        let numeric = (eval(i, eps)? - eval(i, -eps)?) / (2.0 * f64::from(eps));
        let analytic = f64::from(g[i]);
        if !close(numeric, analytic, rel_tol) {
            return Err(format!(
                "input element {i}: numeric {numeric}, analytic {analytic}"
            ));
        }
        checked += 1;
    }
    if checked == 0 {
        return Err("the input is empty".into());
    }
    Ok(checked)
}

/// For every variable in `vars`, checks the gradient in `grads` of its largest-gradient
/// element against central differences of `loss` (which must evaluate the same scalar
/// `grads` came from, reading the variables' current values) with step `eps`:
/// `|numeric − analytic| ≤ rel_tol·max(|numeric|, |analytic|) + abs_tol`. Every variable is
/// restored afterwards.
pub fn check_parameter_gradients(
    vars: &[(String, Var)],
    loss: &dyn Fn() -> candle_core::Result<f64>,
    grads: &GradStore,
    eps: f32,
    rel_tol: f64,
    abs_tol: f64,
) -> Result<(), String> {
    for (name, var) in vars {
        let dims = var.as_tensor().dims().to_vec();
        let gv = grads
            .get(var.as_tensor())
            .ok_or_else(|| format!("no gradient for {name}"))?
            .flatten_all()
            .and_then(|t| t.to_vec1::<f32>())
            .map_err(msg)?;
        let base = var
            .as_tensor()
            .flatten_all()
            .and_then(|t| t.to_vec1::<f32>())
            .map_err(msg)?;
        let Some(i) = gv
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .map(|(i, _)| i)
        else {
            continue;
        };
        let eval = |d: f32| -> Result<f64, String> {
            let mut v = base.clone();
            v[i] += d;
            var.set(&Tensor::from_vec(v, dims.as_slice(), &Device::Cpu).map_err(msg)?)
                .map_err(msg)?;
            loss().map_err(msg)
        };
        let numeric = (eval(eps)? - eval(-eps)?) / (2.0 * f64::from(eps));
        var.set(&Tensor::from_vec(base, dims.as_slice(), &Device::Cpu).map_err(msg)?)
            .map_err(msg)?;
        let analytic = f64::from(gv[i]);
        if (numeric - analytic).abs() > rel_tol * numeric.abs().max(analytic.abs()) + abs_tol {
            return Err(format!(
                "{name}[{i}]: numeric {numeric}, analytic {analytic}"
            ));
        }
    }
    Ok(())
}
