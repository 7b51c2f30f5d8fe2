//! Power to decibels, with librosa's `power_to_db` semantics.

/// The reference level that maps to 0 dB.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DbRef {
    /// A fixed reference power (librosa's default is 1.0).
    Value(f32),
    /// The largest value of the input (librosa's `ref=np.max`).
    Max,
}

/// Parameters of [`power_to_db`]; the default equals librosa's (`ref=1.0`, `amin=1e-10`,
/// `top_db=80`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DbConfig {
    /// Reference level.
    pub reference: DbRef,
    /// Floor applied to the input and reference before the logarithm.
    pub amin: f32,
    /// Clip everything more than this many dB below the peak; `None` = no clipping.
    pub top_db: Option<f32>,
}

impl Default for DbConfig {
    fn default() -> Self {
        Self {
            reference: DbRef::Value(1.0),
            amin: 1e-10,
            top_db: Some(80.0),
        }
    }
}

/// Converts power values to dB in place:
/// `10·log10(max(amin, S)) − 10·log10(max(amin, ref))`, then clips to `max − top_db`.
///
/// Non-positive `amin` is treated as librosa's default 1e-10 (librosa raises instead);
/// NaN inputs stay NaN.
///
/// ```
/// let mut s = vec![1.0f32, 0.1, 0.0];
/// dsp_mel::power_to_db(&mut s, &dsp_mel::DbConfig::default());
/// assert_eq!(s, vec![0.0, -10.0, -80.0]);
/// ```
pub fn power_to_db(values: &mut [f32], cfg: &DbConfig) {
    let amin = if cfg.amin > 0.0 { cfg.amin } else { 1e-10 };
    let reference = match cfg.reference {
        DbRef::Value(v) => v.abs(),
        DbRef::Max => values.iter().fold(0.0f32, |m, &v| m.max(v)),
    };
    let offset = 10.0 * reference.max(amin).log10();
    let mut peak = f32::NEG_INFINITY;
    for v in values.iter_mut() {
        *v = 10.0 * v.max(amin).log10() - offset;
        peak = peak.max(*v);
    }
    if let Some(top) = cfg.top_db {
        let floor = peak - top.abs();
        for v in values.iter_mut() {
            *v = v.max(floor);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_reference_puts_peak_at_zero() {
        let mut s = vec![4.0f32, 2.0, 1e-20];
        power_to_db(
            &mut s,
            &DbConfig {
                reference: DbRef::Max,
                amin: 1e-10,
                top_db: None,
            },
        );
        assert_eq!(s[0], 0.0);
        assert!((s[1] + 3.0103).abs() < 1e-3);
        assert!((s[2] - (-100.0 - 6.0206)).abs() < 1e-3);
    }

    #[test]
    fn empty_is_fine() {
        power_to_db(&mut [], &DbConfig::default());
    }
}
