//! Weights files: safetensors with the parameters (f16 or f32) and, in the metadata, the
//! format version, the network's [`Config`], the normalisation ([`MelStats`], [`TargetSpace`])
//! and the training record. [`GruBaseline::pretrained`] embeds the shipped default.

use std::collections::HashMap;
use std::path::Path;

use candle_core::{DType, Device, Tensor};
use candle_nn::VarBuilder;
use serde::{Deserialize, Serialize};

use crate::config::Config;
use crate::error::{GruError, Result};
use crate::model::GruBaseline;
use crate::norm::{MelStats, TargetSpace};

/// Value of the `format` metadata key.
pub const FORMAT_NAME: &str = "gru-baseline";
/// Version of the weights format this crate writes. Version 2 added the target
/// coordinates' statistics and the output delay; version 1 files (neither) still load.
pub const FORMAT_VERSION: u32 = 2;

/// The shipped default weights (trained on the synthetic corpus; see the crate README).
static PRETRAINED: &[u8] = include_bytes!("../weights/gru_baseline.safetensors");

/// How the parameters are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum StorageDtype {
    /// Half precision (half the size; ~1e-3 relative rounding).
    F16,
    /// Single precision (exact).
    F32,
}

/// How a weights file was trained, kept in its metadata.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TrainingRecord {
    /// The command line (or description) that trained it.
    pub command: String,
    /// The training data folder and its layout.
    pub data: String,
    /// Training seed.
    pub seed: u64,
    /// Epochs run.
    pub epochs: usize,
    /// Epoch (1-based) whose weights these are (best validation loss).
    pub best_epoch: usize,
    /// Validation loss of these weights (the training loss's own weighting).
    pub val_loss: f64,
    /// Whether the right-arm weighted loss was used.
    pub weighted_loss: bool,
    /// Training frames (30 fps).
    pub train_frames: usize,
    /// Wall time of the training, seconds.
    pub wall_time_s: f64,
}

fn json<T: Serialize>(value: &T) -> Result<String> {
    serde_json::to_string(value)
        .map_err(|e| GruError::Config(format!("cannot serialise metadata ({e})")))
}

fn weights_err(path: &Path, reason: impl Into<String>) -> GruError {
    GruError::Weights {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}

/// Every parameter's name and shape for `cfg`, in file order.
pub fn expected_shapes(cfg: &Config) -> Vec<(String, Vec<usize>)> {
    let mut out = Vec::new();
    let mut input = cfg.n_mels;
    for (l, &h) in cfg.hidden.iter().enumerate() {
        out.push((format!("gru{l}.weight_ih_l0"), vec![3 * h, input]));
        out.push((format!("gru{l}.weight_hh_l0"), vec![3 * h, h]));
        out.push((format!("gru{l}.bias_ih_l0"), vec![3 * h]));
        out.push((format!("gru{l}.bias_hh_l0"), vec![3 * h]));
        input = h;
    }
    out.push(("head.weight".into(), vec![cfg.outputs(), input]));
    out.push(("head.bias".into(), vec![cfg.outputs()]));
    out
}

fn meta_json<T: serde::de::DeserializeOwned>(
    meta: &HashMap<String, String>,
    key: &str,
    path: &Path,
) -> Result<T> {
    let text = meta.get(key).ok_or_else(|| {
        weights_err(
            path,
            format!("metadata has no `{key}`; not a gru-baseline weights file"),
        )
    })?;
    serde_json::from_str(text)
        .map_err(|e| weights_err(path, format!("metadata `{key}` is unreadable ({e})")))
}

impl GruBaseline {
    /// The shipped default weights (SPEC §8 network, right-arm weighted loss, trained on the
    /// synthetic corpus; see the crate README for the training record).
    ///
    /// ```
    /// let net = gru_baseline::GruBaseline::pretrained()?;
    /// assert_eq!(net.config(), &gru_baseline::Config::default());
    /// # Ok::<(), gru_baseline::GruError>(())
    /// ```
    pub fn pretrained() -> Result<Self> {
        Ok(Self::from_bytes(PRETRAINED, Path::new("<pretrained>"))?.0)
    }

    /// Reads a weights file written by [`GruBaseline::save`] (e.g. by
    /// `violin-skeleton train gru`), checking format, version and every tensor's shape.
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        Ok(Self::load_with_record(path)?.0)
    }

    /// [`GruBaseline::load`], also returning the training record when the file has one.
    pub fn load_with_record(path: impl AsRef<Path>) -> Result<(Self, Option<TrainingRecord>)> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => weights_err(
                path,
                "file not found; check the path or train one with `violin-skeleton train gru`",
            ),
            _ => weights_err(path, format!("cannot read ({e})")),
        })?;
        Self::from_bytes(&bytes, path)
    }

    /// Parses weights from memory; `path` names them in errors.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<(Self, Option<TrainingRecord>)> {
        let (_, header) = safetensors::SafeTensors::read_metadata(bytes)
            .map_err(|e| weights_err(path, format!("not a safetensors file ({e})")))?;
        let empty = HashMap::new();
        let meta = header.metadata().as_ref().unwrap_or(&empty);
        match meta.get("format") {
            Some(f) if f == FORMAT_NAME => {}
            other => {
                return Err(weights_err(
                    path,
                    format!(
                        "format is {:?}, expected \"{FORMAT_NAME}\": this is not a Method 1 (GRU) weights file",
                        other.map(String::as_str).unwrap_or("missing")
                    ),
                ))
            }
        }
        let version: u32 = meta_json(meta, "version", path)?;
        if version == 0 || version > FORMAT_VERSION {
            return Err(weights_err(
                path,
                format!("format version {version}, this build reads versions 1 to {FORMAT_VERSION}; retrain or use a matching build"),
            ));
        }
        let cfg: Config = meta_json(meta, "config", path)?;
        cfg.validate()
            .map_err(|e| weights_err(path, format!("config: {e}")))?;
        let mel_stats: MelStats = meta_json(meta, "mel_stats", path)?;
        let target: TargetSpace = meta_json(meta, "target_space", path)?;
        let record: Option<TrainingRecord> = match meta.get("training") {
            Some(_) => Some(meta_json(meta, "training", path)?),
            None => None,
        };
        let tensors = candle_core::safetensors::load_buffer(bytes, &Device::Cpu).map_err(|e| {
            weights_err(
                path,
                format!("cannot read the tensors ({e}); the file may be truncated"),
            )
        })?;
        let mut f32_tensors = HashMap::new();
        for (name, shape) in expected_shapes(&cfg) {
            let t = tensors
                .get(&name)
                .ok_or_else(|| weights_err(path, format!("tensor `{name}` is missing")))?;
            if t.dims() != shape.as_slice() {
                return Err(weights_err(
                    path,
                    format!(
                        "tensor `{name}` has shape {:?}, the config needs {shape:?}",
                        t.dims()
                    ),
                ));
            }
            let t = t.to_dtype(DType::F32)?;
            if t.flatten_all()?
                .to_vec1::<f32>()?
                .iter()
                .any(|v| !v.is_finite())
            {
                return Err(weights_err(
                    path,
                    format!("tensor `{name}` holds NaN or infinity"),
                ));
            }
            f32_tensors.insert(name, t);
        }
        if let Some(extra) = tensors.keys().find(|k| !f32_tensors.contains_key(*k)) {
            return Err(weights_err(
                path,
                format!("unexpected tensor `{extra}` for this config"),
            ));
        }
        let vb = VarBuilder::from_tensors(f32_tensors, DType::F32, &Device::Cpu);
        let mut net = GruBaseline::new(&cfg, vb)?;
        net.set_normalization(mel_stats, target)
            .map_err(|e| weights_err(path, format!("normalisation: {e}")))?;
        Ok((net, record))
    }

    /// The file's bytes: parameters as `dtype`, config, normalisation and `record` in the
    /// metadata.
    pub fn to_bytes(
        &self,
        dtype: StorageDtype,
        record: Option<&TrainingRecord>,
    ) -> Result<Vec<u8>> {
        let mut meta = HashMap::new();
        meta.insert("format".to_string(), FORMAT_NAME.to_string());
        meta.insert("version".to_string(), FORMAT_VERSION.to_string());
        meta.insert("config".to_string(), json(self.config())?);
        meta.insert("mel_stats".to_string(), json(self.mel_stats())?);
        meta.insert("target_space".to_string(), json(self.target_space())?);
        if let Some(r) = record {
            meta.insert("training".to_string(), json(r)?);
        }
        let dt = match dtype {
            StorageDtype::F16 => DType::F16,
            StorageDtype::F32 => DType::F32,
        };
        let mut tensors: Vec<(String, Tensor)> = Vec::new();
        for (name, t) in self.named_parameters() {
            tensors.push((name, t.detach().to_dtype(dt)?.contiguous()?));
        }
        tensors.sort_by(|a, b| a.0.cmp(&b.0));
        safetensors::serialize(tensors.iter().map(|(n, t)| (n.as_str(), t)), Some(meta))
            .map(net_core::file::canonical_header)
            .map_err(|e| GruError::Config(format!("cannot serialise the weights ({e})")))
    }

    /// Writes a weights file atomically (temporary file in the same folder, then rename).
    pub fn save(
        &self,
        path: impl AsRef<Path>,
        dtype: StorageDtype,
        record: Option<&TrainingRecord>,
    ) -> Result<()> {
        write_atomically(path.as_ref(), &self.to_bytes(dtype, record)?)
    }
}

/// Writes `bytes` to `path` through a temporary file that is renamed at the end.
pub(crate) fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    atomic_file::write_bytes_atomically(path, bytes).map_err(|e| {
        weights_err(
            path,
            format!("cannot write ({e}); check the folder exists and is writable"),
        )
    })
}
