//! Learning-rate schedules: the rate of every optimiser step from the peak rate, the step
//! index and the length of training.

use serde::{Deserialize, Serialize};

/// How the learning rate moves over training.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum LrSchedule {
    /// `peak × per_epoch^epoch`: a fixed rate within an epoch, shrinking between epochs.
    Exponential {
        /// Factor per epoch (e.g. 0.93).
        per_epoch: f64,
    },
    /// Linear warm-up from `peak / 10` to `peak` over the first `warmup_fraction` of all
    /// steps, then a half cosine down to `peak × final_fraction` at the last step.
    WarmupCosine {
        /// Share of all steps spent warming up (0..1).
        warmup_fraction: f64,
        /// The last step's rate as a share of the peak.
        final_fraction: f64,
    },
}

impl LrSchedule {
    /// The rate of step `step` (0-based, counted over all epochs) when training runs
    /// `steps_per_epoch × epochs` steps in all.
    ///
    /// ```
    /// use net_core::LrSchedule;
    /// let s = LrSchedule::WarmupCosine { warmup_fraction: 0.1, final_fraction: 0.01 };
    /// assert!((s.rate(1e-3, 0, 100, 10) - 1e-4).abs() < 1e-12);      // start of warm-up
    /// assert!((s.rate(1e-3, 100, 100, 10) - 1e-3).abs() < 1e-12);    // peak after 10 %
    /// assert!((s.rate(1e-3, 999, 100, 10) - 1e-5).abs() < 1e-9);     // last step
    /// let e = LrSchedule::Exponential { per_epoch: 0.5 };
    /// assert!((e.rate(1e-3, 250, 100, 10) - 2.5e-4).abs() < 1e-12);  // epoch 2
    /// ```
    pub fn rate(&self, peak: f64, step: usize, steps_per_epoch: usize, epochs: usize) -> f64 {
        let steps_per_epoch = steps_per_epoch.max(1);
        match *self {
            LrSchedule::Exponential { per_epoch } => {
                peak * per_epoch.powi((step / steps_per_epoch) as i32)
            }
            LrSchedule::WarmupCosine {
                warmup_fraction,
                final_fraction,
            } => {
                let total = (steps_per_epoch * epochs.max(1)) as f64;
                let warm = (warmup_fraction.clamp(0.0, 1.0) * total).round();
                let s = step as f64;
                if s < warm {
                    peak * (0.1 + 0.9 * s / warm)
                } else {
                    let span = (total - 1.0 - warm).max(1.0);
                    let progress = ((s - warm) / span).min(1.0);
                    let low = peak * final_fraction;
                    low + (peak - low) * 0.5 * (1.0 + (std::f64::consts::PI * progress).cos())
                }
            }
        }
    }
}
