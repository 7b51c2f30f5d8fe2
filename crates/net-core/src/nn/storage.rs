//! Reading the custom ops' inputs out of candle's CPU storage.

/// The values of a contiguous f32 CPU storage (the custom ops' inputs), without copying.
pub(super) fn f32_contiguous<'a>(
    storage: &'a candle_core::CpuStorage,
    layout: &candle_core::Layout,
) -> candle_core::Result<&'a [f32]> {
    let data = match storage {
        candle_core::CpuStorage::F32(v) => v.as_slice(),
        _ => candle_core::bail!("only f32 tensors are supported"),
    };
    match layout.contiguous_offsets() {
        Some((start, end)) => Ok(&data[start..end]),
        None => candle_core::bail!("the op needs a contiguous input"),
    }
}
