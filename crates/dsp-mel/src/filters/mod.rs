//! Filters that match scipy: Butterworth design, zero-phase `filtfilt`, and median filters.

mod butterworth;
mod filtfilt;
mod median;

pub use butterworth::{Butterworth, SecondOrderSection, TransferFunction};
pub use filtfilt::{filtfilt, filtfilt_padlen, filtfilt_tf, lfilter, lfilter_zi};
pub use median::{median_filter, EdgeMode};
