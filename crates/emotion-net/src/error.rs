//! The crate's error type.

/// Everything emotion-net can fail with.
#[derive(Debug, thiserror::Error)]
pub enum EmotionError {
    /// A tensor, file, weights or data error from the shared network layer (bowing-net's
    /// `nn` building blocks and weights files).
    #[error(transparent)]
    Net(#[from] bowing_net::NetError),
    /// A weights or checkpoint file could not be read, written or used.
    #[error(transparent)]
    Store(#[from] net_store::StoreError),
    /// A tensor operation failed.
    #[error("tensor operation failed: {0}")]
    Candle(#[from] candle_core::Error),
    /// Audio decoding or the mel spectrogram failed.
    #[error(transparent)]
    Dsp(#[from] dsp_mel::DspError),
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, EmotionError>;
