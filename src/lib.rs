//! violin-skeleton: turn a solo violin recording into a violinist skeleton animation.
pub use dsp_mel;
