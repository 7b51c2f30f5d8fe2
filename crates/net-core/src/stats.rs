//! Per-band input normalisation statistics.

use std::collections::HashMap;

use candle_core::{Device, Tensor};
use candle_nn::VarMap;
use ndarray::ArrayView2;

use crate::error::Result;

/// Mean and standard deviation (floored at 1e-3) of every band (column) over all frames
/// (rows) of `spectrograms`; bands beyond `bands` are ignored.
///
/// ```
/// let a = ndarray::array![[0.0f32, 10.0], [2.0, 10.0]];
/// let (mean, std) = net_core::band_statistics([a.view()], 2);
/// assert_eq!(mean, vec![1.0, 10.0]);
/// assert_eq!(std, vec![1.0, 1e-3]);
/// ```
pub fn band_statistics<'a>(
    spectrograms: impl IntoIterator<Item = ArrayView2<'a, f32>>,
    bands: usize,
) -> (Vec<f32>, Vec<f32>) {
    let mut sum = vec![0.0f64; bands];
    let mut sq = vec![0.0f64; bands];
    let mut n = 0usize;
    for mel in spectrograms {
        for row in mel.rows() {
            for (k, &v) in row.iter().enumerate().take(bands) {
                sum[k] += f64::from(v);
                sq[k] += f64::from(v) * f64::from(v);
            }
            n += 1;
        }
    }
    let n = n.max(1) as f64;
    let mean = sum.iter().map(|s| (s / n) as f32).collect();
    let std = sq
        .iter()
        .zip(&sum)
        .map(|(q, s)| ((q / n - (s / n).powi(2)).max(0.0).sqrt().max(1e-3)) as f32)
        .collect();
    (mean, std)
}

/// Computes [`band_statistics`] of `spectrograms` and writes them into the variables
/// `norm.mean` and `norm.std` of `varmap`: the input normalisation a network stores with its
/// weights (variables `varmap` lacks are left alone).
pub fn set_band_statistics<'a>(
    varmap: &VarMap,
    spectrograms: impl IntoIterator<Item = ArrayView2<'a, f32>>,
    bands: usize,
) -> Result<()> {
    let (mean, std) = band_statistics(spectrograms, bands);
    let values = HashMap::from([
        (
            "norm.mean".to_string(),
            Tensor::new(mean.as_slice(), &Device::Cpu)?,
        ),
        (
            "norm.std".to_string(),
            Tensor::new(std.as_slice(), &Device::Cpu)?,
        ),
    ]);
    crate::vars::set_vars(varmap, &values)
}
