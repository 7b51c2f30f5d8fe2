//! Python bindings of violin-skeleton: the `violin_skeleton._native` extension module that
//! the `violin_skeleton` package (in `python/`) wraps.
//!
//! Inputs are a path or a NumPy array of samples (`input`); results are `analysis`'s
//! `Analysis` and `motion`'s `Motion`, computed by `pipeline`'s `Pipeline` with the GIL
//! released; every failure is a `ViolinSkeletonError` (`errors`).

mod analysis;
mod errors;
mod features;
mod input;
mod motion;
mod output;
mod pipeline;

use pyo3::prelude::*;

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<analysis::PyAnalysis>()?;
    m.add_class::<motion::PyMotion>()?;
    m.add_class::<pipeline::PyPipeline>()?;
    m.add_function(wrap_pyfunction!(features::features, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("MAX_CHANNELS", input::MAX_CHANNELS)?;
    Ok(())
}
