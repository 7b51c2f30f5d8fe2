//! Arousal over time: [`ArousalCurve`] (DEAM convention, 2 Hz) and the arousal proxy that
//! labels the synthetic corpus and MIDI input ([`arousal_proxy`]).

use serde::{Deserialize, Serialize};

/// Musical arousal over time (DEAM convention): `values[i]` at `i / rate_hz` seconds, each
/// in [-1, 1] (calm … excited).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArousalCurve {
    /// Values per second (2 for DEAM and the emotion network).
    pub rate_hz: f64,
    /// The values, in [-1, 1].
    pub values: Vec<f32>,
}

impl ArousalCurve {
    /// The rate of the emotion network's output and of DEAM annotations.
    pub const DEAM_RATE_HZ: f64 = 2.0;

    /// A curve at [`ArousalCurve::DEAM_RATE_HZ`].
    pub fn deam(values: Vec<f32>) -> ArousalCurve {
        ArousalCurve {
            rate_hz: Self::DEAM_RATE_HZ,
            values,
        }
    }

    /// A curve whose finite values are clipped to [-1, 1] (NaN stays NaN and is rejected by
    /// [`crate::Performance::new`]).
    ///
    /// ```
    /// let c = performance::ArousalCurve::clamped(2.0, vec![-3.0, 0.5, 7.0]);
    /// assert_eq!(c.values, vec![-1.0, 0.5, 1.0]);
    /// ```
    pub fn clamped(rate_hz: f64, values: Vec<f32>) -> ArousalCurve {
        ArousalCurve {
            rate_hz,
            values: values.into_iter().map(|v| v.clamp(-1.0, 1.0)).collect(),
        }
    }

    /// Time of value `index`, seconds.
    pub fn time_s(&self, index: usize) -> f64 {
        index as f64 / self.rate_hz
    }
}

/// [`crate::arousal_proxy`] of sounding spans `(onset_s, offset_s, dynamic 0..=1)` in onset order
/// (e.g. a `Performance`'s notes and dynamics).
///
/// ```
/// // 4 s of quarter notes at 120 bpm, forte, then 2 s of silence.
/// let spans: Vec<(f64, f64, f32)> = (0..8).map(|i| (i as f64 * 0.5, i as f64 * 0.5 + 0.45, 0.8)).collect();
/// let a = performance::arousal_proxy_of_spans(&spans, 6.0);
/// assert_eq!(a.len(), 12);
/// assert!(a[3] > 0.3 && a[11] < -0.5);
/// ```
pub fn arousal_proxy_of_spans(spans: &[(f64, f64, f32)], duration_s: f64) -> Vec<f32> {
    const SAMPLES_PER_FRAME: usize = 50;
    let n = (duration_s * 2.0).ceil() as usize;
    if n == 0 {
        return Vec::new();
    }
    // The louder sounding level every 10 ms (0 in silence).
    let mut level = vec![0.0f64; n * SAMPLES_PER_FRAME];
    let per_s = 2.0 * SAMPLES_PER_FRAME as f64;
    for &(on, off, dynamic) in spans {
        let first = (on * per_s).ceil().max(0.0) as usize;
        let last = ((off * per_s).ceil().max(0.0) as usize).min(level.len());
        for v in level.iter_mut().take(last).skip(first) {
            *v = v.max(f64::from(dynamic));
        }
    }
    let onsets: Vec<f64> = spans.iter().map(|s| s.0).collect();
    let raw: Vec<f64> = (0..n)
        .map(|k| {
            let frame = &level[k * SAMPLES_PER_FRAME..(k + 1) * SAMPLES_PER_FRAME];
            let d = frame.iter().sum::<f64>() / SAMPLES_PER_FRAME as f64;
            let t = k as f64 * 0.5 + 0.25;
            let density = onsets.iter().filter(|&&o| (o - t).abs() <= 1.0).count() as f64 / 2.0;
            (1.8 * (d - 0.45) + 0.5 * (density - 3.0) / 3.0).tanh()
        })
        .collect();
    (0..n)
        .map(|k| {
            let a = raw[k.saturating_sub(1)];
            let b = raw[k];
            let c = raw[(k + 1).min(n - 1)];
            ((a + 2.0 * b + c) / 4.0) as f32
        })
        .collect()
}
