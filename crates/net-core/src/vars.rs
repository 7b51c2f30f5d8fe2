//! Variables of a candle `VarMap` by name: shapes, copies, trainable subsets, loading from a
//! file's tensors, and seeded initialisation.

use std::collections::HashMap;
use std::path::Path;

use crate::rng::Rng;
use candle_core::{Device, Tensor};
use candle_nn::VarMap;

use crate::error::{Result, StoreError};

/// The `(name, shape)` of every variable of `varmap`, sorted by name.
pub fn var_shapes(varmap: &VarMap) -> Vec<(String, Vec<usize>)> {
    let mut out: Vec<(String, Vec<usize>)> = match varmap.data().lock() {
        Ok(data) => data
            .iter()
            .map(|(k, v)| (k.clone(), v.as_tensor().dims().to_vec()))
            .collect(),
        Err(_) => Vec::new(),
    };
    out.sort();
    out
}

/// The variables of `varmap` as `(name, tensor)` pairs, sorted by name.
pub fn var_tensors(varmap: &VarMap) -> Vec<(String, Tensor)> {
    let mut out: Vec<(String, Tensor)> = match varmap.data().lock() {
        Ok(data) => data
            .iter()
            .map(|(k, v)| (k.clone(), v.as_detached_tensor()))
            .collect(),
        Err(_) => Vec::new(),
    };
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// Copies of the variables of `varmap` as `(name, tensor)` pairs, sorted by name: a snapshot
/// that later training steps do not change (e.g. a detector built during training).
pub fn copied_tensors(varmap: &VarMap) -> candle_core::Result<Vec<(String, Tensor)>> {
    var_tensors(varmap)
        .into_iter()
        .map(|(n, t)| t.copy().map(|t| (n, t)))
        .collect()
}

/// The trainable variables of `varmap` (all but those `frozen` says), sorted by name.
pub fn trainable_vars(
    varmap: &VarMap,
    frozen: impl Fn(&str) -> bool,
) -> Vec<(String, candle_core::Var)> {
    let mut out: Vec<(String, candle_core::Var)> = match varmap.data().lock() {
        Ok(data) => data
            .iter()
            .filter(|(k, _)| !frozen(k))
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect(),
        Err(_) => Vec::new(),
    };
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// Overwrites the variables of `varmap` that `tensors` has (same shapes required).
pub fn load_into(varmap: &VarMap, tensors: &HashMap<String, Tensor>, path: &Path) -> Result<()> {
    let data = varmap
        .data()
        .lock()
        .map_err(|_| StoreError::Config("variable store poisoned".into()))?;
    for (name, var) in data.iter() {
        let t = tensors
            .get(name)
            .ok_or_else(|| StoreError::weights(path, format!("tensor \"{name}\" is missing")))?;
        if t.dims() != var.as_tensor().dims() {
            return Err(StoreError::weights(
                path,
                format!(
                    "tensor \"{name}\" has shape {:?}, the network needs {:?}",
                    t.dims(),
                    var.as_tensor().dims()
                ),
            ));
        }
        var.set(t)?;
    }
    Ok(())
}

/// Seeded initialisation of every variable of `varmap`, in name order: `rule(name, shape)`
/// gives `Some(bound)` for uniform values in ±bound, or `None` to leave the variable as it is
/// (e.g. biases created as zeros).
pub fn init_seeded(
    varmap: &VarMap,
    seed: u64,
    rule: impl Fn(&str, &[usize]) -> Option<f64>,
) -> Result<()> {
    let mut rng = Rng::new(seed);
    for (name, var) in trainable_vars(varmap, |_| false) {
        let dims = var.as_tensor().dims().to_vec();
        if let Some(bound) = rule(&name, &dims) {
            let n: usize = dims.iter().product();
            let values: Vec<f32> = (0..n).map(|_| rng.uniform(-bound, bound) as f32).collect();
            var.set(&Tensor::from_vec(values, dims.as_slice(), &Device::Cpu)?)?;
        }
    }
    Ok(())
}

/// Overwrites the variables of `varmap` named in `values` (others are left alone; names
/// `varmap` lacks are ignored).
pub fn set_vars(varmap: &VarMap, values: &HashMap<String, Tensor>) -> Result<()> {
    let data = varmap
        .data()
        .lock()
        .map_err(|_| StoreError::Config("variable store poisoned".into()))?;
    for (name, t) in values {
        if let Some(v) = data.get(name) {
            v.set(t)?;
        }
    }
    Ok(())
}

/// Keras's default initialisation (Glorot/Xavier uniform) bound for a weight of shape
/// `(out, in, k…)`: `sqrt(6 / (fan_in + fan_out))`.
///
/// ```
/// assert!((net_core::vars::glorot_bound(&[64, 384]) - (6.0f64 / 448.0).sqrt()).abs() < 1e-12);
/// ```
pub fn glorot_bound(dims: &[usize]) -> f64 {
    let receptive: usize = dims.iter().skip(2).product();
    let fan_out = dims.first().copied().unwrap_or(1) * receptive.max(1);
    let fan_in = dims.get(1).copied().unwrap_or(1) * receptive.max(1);
    (6.0 / (fan_in + fan_out).max(1) as f64).sqrt()
}
