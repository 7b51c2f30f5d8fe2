//! Weights files: safetensors with the network's name, format version, configuration and
//! anything else a loader needs in the string metadata; f32 tensors only.
//!
//! ```
//! use std::collections::HashMap;
//! use candle_core::{Device, Tensor};
//! use net_core::file::{decode, encode, KEY_FORMAT, KEY_VERSION};
//! let t = Tensor::new(&[1f32, 2.0], &Device::Cpu)?;
//! let meta = HashMap::from([
//!     (KEY_FORMAT.to_string(), "demo-net".to_string()),
//!     (KEY_VERSION.to_string(), "1".to_string()),
//! ]);
//! let bytes = encode(&[("w".to_string(), t)], meta)?;
//! let file = decode(&bytes, "demo.safetensors".as_ref())?;
//! file.check_format("demo.safetensors".as_ref(), "demo-net", 1)?;
//! assert!(file.check_format("demo.safetensors".as_ref(), "other-net", 1).is_err());
//! assert_eq!(file.tensors["w"].to_vec1::<f32>()?, vec![1.0, 2.0]);
//! # Ok::<(), net_core::StoreError>(())
//! ```

use std::collections::HashMap;
use std::path::Path;

use candle_core::{Device, Tensor};
use safetensors::tensor::{Dtype, SafeTensors, TensorView};

use crate::error::{Result, StoreError};

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
        self.metadata.get(key).map(String::as_str).ok_or_else(|| {
            StoreError::weights(path, format!("the metadata has no \"{key}\" entry"))
        })
    }

    /// Checks the network name and version written by [`encode`].
    pub fn check_format(&self, path: &Path, format: &str, version: u32) -> Result<()> {
        let found = self.meta(KEY_FORMAT, path)?;
        if found != format {
            return Err(StoreError::weights(
                path,
                format!("it holds \"{found}\" weights, this loader reads \"{format}\""),
            ));
        }
        let v = self.meta(KEY_VERSION, path)?;
        if v != version.to_string() {
            return Err(StoreError::weights(
                path,
                format!("format version {v}, this build reads version {version}: retrain with this version"),
            ));
        }
        Ok(())
    }

    /// The metadata value of `key` parsed as JSON, or an error naming `path` and the key.
    pub fn meta_json<T: serde::de::DeserializeOwned>(&self, key: &str, path: &Path) -> Result<T> {
        serde_json::from_str(self.meta(key, path)?)
            .map_err(|e| StoreError::weights(path, format!("bad \"{key}\" metadata ({e})")))
    }

    /// The tensors named in `expected`, in that order, after checking their shapes
    /// ([`TensorFile::check_shapes`]); tensors the file has beyond them are ignored.
    pub fn take_expected(
        &self,
        path: &Path,
        expected: &[(String, Vec<usize>)],
    ) -> Result<Vec<(String, Tensor)>> {
        self.check_shapes(path, expected)?;
        Ok(expected
            .iter()
            .filter_map(|(name, _)| self.tensors.get(name).map(|t| (name.clone(), t.clone())))
            .collect())
    }

    /// Checks that every `(name, shape)` is present with that shape.
    pub fn check_shapes(&self, path: &Path, expected: &[(String, Vec<usize>)]) -> Result<()> {
        for (name, shape) in expected {
            let t = self.tensors.get(name).ok_or_else(|| {
                StoreError::weights(path, format!("tensor \"{name}\" is missing"))
            })?;
            if t.dims() != shape.as_slice() {
                return Err(StoreError::weights(
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
            .map_err(|e| StoreError::Config(format!("tensor {name}: {e}")))?;
        views.push((name.clone(), view));
    }
    safetensors::serialize(views, Some(metadata))
        .map(canonical_header)
        .map_err(|e| StoreError::Config(format!("safetensors: {e}")))
}

/// The same safetensors bytes with the JSON header's keys sorted (metadata included), so
/// that the same weights and metadata always give the same file, byte for byte (the
/// safetensors writer takes the metadata as a `HashMap`, whose order changes from run to
/// run). The header stays padded with spaces to a multiple of 8 bytes; bytes that are not
/// a readable header are returned unchanged.
pub fn canonical_header(bytes: Vec<u8>) -> Vec<u8> {
    let Some(len_bytes) = bytes.get(..8) else {
        return bytes;
    };
    let mut n = [0u8; 8];
    n.copy_from_slice(len_bytes);
    let Ok(n) = usize::try_from(u64::from_le_bytes(n)) else {
        return bytes;
    };
    let Some(header) = n.checked_add(8).and_then(|end| bytes.get(8..end)) else {
        return bytes;
    };
    // serde_json's map is ordered by key (no `preserve_order`), so this sorts every level.
    let Ok(value) = serde_json::from_slice::<serde_json::Value>(header) else {
        return bytes;
    };
    let Ok(mut sorted) = serde_json::to_vec(&value) else {
        return bytes;
    };
    while sorted.len() % 8 != 0 {
        sorted.push(b' ');
    }
    let mut out = Vec::with_capacity(bytes.len() + 8);
    out.extend_from_slice(&(sorted.len() as u64).to_le_bytes());
    out.extend_from_slice(&sorted);
    out.extend_from_slice(&bytes[8 + n..]);
    out
}

/// Parses safetensors bytes (f32 tensors only); `path` names the source in errors.
pub fn decode(bytes: &[u8], path: &Path) -> Result<TensorFile> {
    let bad = |e: &dyn std::fmt::Display| {
        StoreError::weights(
            path,
            format!("not a readable safetensors file ({e}); was it truncated?"),
        )
    };
    let (_, header) = SafeTensors::read_metadata(bytes).map_err(|e| bad(&e))?;
    let st = SafeTensors::deserialize(bytes).map_err(|e| bad(&e))?;
    let mut tensors = HashMap::new();
    for (name, view) in st.tensors() {
        if view.dtype() != Dtype::F32 {
            return Err(StoreError::weights(
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
            return Err(StoreError::weights(
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
        .map_err(|e| StoreError::io(path, format!("cannot read the weights file ({e})")))?;
    decode(&bytes, path)
}

/// Writes bytes to `path` through a temporary file in the same folder (never half-written).
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    atomic_file::write_bytes_atomically(path, bytes)
        .map_err(|e| StoreError::io(path, format!("cannot write ({e}); is the folder writable?")))
}

/// The metadata of a network's weights file: its format name and version (the keys
/// [`TensorFile::check_format`] reads) plus `entries` (e.g. `config`, `training`).
pub fn metadata(format: &str, version: u32, entries: &[(&str, String)]) -> HashMap<String, String> {
    let mut meta: HashMap<String, String> = entries
        .iter()
        .map(|(k, v)| ((*k).to_string(), v.clone()))
        .collect();
    meta.insert(KEY_FORMAT.to_string(), format.to_string());
    meta.insert(KEY_VERSION.to_string(), version.to_string());
    meta
}

/// `value` as JSON metadata.
pub fn to_json<T: serde::Serialize>(value: &T) -> Result<String> {
    serde_json::to_string(value)
        .map_err(|e| StoreError::Config(format!("cannot serialise metadata ({e})")))
}
