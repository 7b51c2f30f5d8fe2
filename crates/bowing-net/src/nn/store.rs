//! Weights files: safetensors with the network's name, format version, configuration and
//! anything else a loader needs in the string metadata; f32 tensors only.

use std::collections::HashMap;
use std::path::Path;

use candle_core::{Device, Tensor};
use candle_nn::VarMap;
use corpus::rng::Rng;
use safetensors::tensor::{Dtype, SafeTensors, TensorView};

use crate::error::{NetError, Result};

/// Metadata key naming the network (e.g. `bowing-net`).
pub const KEY_FORMAT: &str = "format";
/// Metadata key holding the format version (decimal).
pub const KEY_VERSION: &str = "format_version";

/// A decoded weights file.
#[derive(Debug, Clone)]
pub struct TensorFile {
    /// The string metadata.
    pub metadata: HashMap<String, String>,
    /// The tensors by name (f32, CPU).
    pub tensors: HashMap<String, Tensor>,
}

impl TensorFile {
    /// The metadata value of `key`, or an error naming `path`.
    pub fn meta(&self, key: &str, path: &Path) -> Result<&str> {
        self.metadata
            .get(key)
            .map(String::as_str)
            .ok_or_else(|| NetError::weights(path, format!("the metadata has no \"{key}\" entry")))
    }

    /// Checks the network name and version written by [`encode`].
    pub fn check_format(&self, path: &Path, format: &str, version: u32) -> Result<()> {
        let found = self.meta(KEY_FORMAT, path)?;
        if found != format {
            return Err(NetError::weights(
                path,
                format!("it holds \"{found}\" weights, this loader reads \"{format}\""),
            ));
        }
        let v = self.meta(KEY_VERSION, path)?;
        if v != version.to_string() {
            return Err(NetError::weights(
                path,
                format!("format version {v}, this build reads version {version}: retrain with this version"),
            ));
        }
        Ok(())
    }

    /// Checks that every `(name, shape)` is present with that shape.
    pub fn check_shapes(&self, path: &Path, expected: &[(String, Vec<usize>)]) -> Result<()> {
        for (name, shape) in expected {
            let t = self
                .tensors
                .get(name)
                .ok_or_else(|| NetError::weights(path, format!("tensor \"{name}\" is missing")))?;
            if t.dims() != shape.as_slice() {
                return Err(NetError::weights(
                    path,
                    format!(
                        "tensor \"{name}\" has shape {:?}, the network needs {shape:?}",
                        t.dims()
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Serialises `tensors` (any shape, converted to f32) and `metadata` to safetensors bytes.
pub fn encode(tensors: &[(String, Tensor)], metadata: HashMap<String, String>) -> Result<Vec<u8>> {
    let mut raw: Vec<(String, Vec<usize>, Vec<u8>)> = Vec::with_capacity(tensors.len());
    for (name, t) in tensors {
        let values = t
            .to_dtype(candle_core::DType::F32)?
            .flatten_all()?
            .to_vec1::<f32>()?;
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        raw.push((name.clone(), t.dims().to_vec(), bytes));
    }
    let mut views = Vec::with_capacity(raw.len());
    for (name, shape, bytes) in &raw {
        let view = TensorView::new(Dtype::F32, shape.clone(), bytes)
            .map_err(|e| NetError::Config(format!("tensor {name}: {e}")))?;
        views.push((name.clone(), view));
    }
    safetensors::serialize(views, Some(metadata))
        .map_err(|e| NetError::Config(format!("safetensors: {e}")))
}

/// Parses safetensors bytes (f32 tensors only); `path` names the source in errors.
pub fn decode(bytes: &[u8], path: &Path) -> Result<TensorFile> {
    let bad = |e: &dyn std::fmt::Display| {
        NetError::weights(
            path,
            format!("not a readable safetensors file ({e}); was it truncated?"),
        )
    };
    let (_, header) = SafeTensors::read_metadata(bytes).map_err(|e| bad(&e))?;
    let st = SafeTensors::deserialize(bytes).map_err(|e| bad(&e))?;
    let mut tensors = HashMap::new();
    for (name, view) in st.tensors() {
        if view.dtype() != Dtype::F32 {
            return Err(NetError::weights(
                path,
                format!("tensor \"{name}\" is {:?}, expected F32", view.dtype()),
            ));
        }
        let values: Vec<f32> = view
            .data()
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        if values.iter().any(|v| !v.is_finite()) {
            return Err(NetError::weights(
                path,
                format!("tensor \"{name}\" holds NaN or infinite values"),
            ));
        }
        tensors.insert(name, Tensor::from_vec(values, view.shape(), &Device::Cpu)?);
    }
    Ok(TensorFile {
        metadata: header.metadata().clone().unwrap_or_default(),
        tensors,
    })
}

/// Reads and parses a safetensors file.
pub fn read(path: &Path) -> Result<TensorFile> {
    let bytes = std::fs::read(path)
        .map_err(|e| NetError::io(path, format!("cannot read the weights file ({e})")))?;
    decode(&bytes, path)
}

/// Writes bytes to `path` through a temporary file in the same folder (never half-written).
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    atomic_file::write_bytes_atomically(path, bytes)
        .map_err(|e| NetError::io(path, format!("cannot write ({e}); is the folder writable?")))
}

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
        .map_err(|_| NetError::Config("variable store poisoned".into()))?;
    for (name, var) in data.iter() {
        let t = tensors
            .get(name)
            .ok_or_else(|| NetError::weights(path, format!("tensor \"{name}\" is missing")))?;
        if t.dims() != var.as_tensor().dims() {
            return Err(NetError::weights(
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
