//! [`Meter`]: how many beats a bar has and how each beat divides.

use serde::{Deserialize, Serialize};

use crate::error::PerformanceError;

/// Beats per bar and subdivisions per beat: 4/4 = `{4, 2}`, 3/4 = `{3, 2}`, 2/4 = `{2, 2}`,
/// 6/8 = `{2, 3}` (two dotted-quarter beats of three eighths).
///
/// ```
/// assert_eq!(performance::Meter::SIX_EIGHT.beats_per_bar, 2);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Meter {
    /// Beats per bar.
    pub beats_per_bar: u8,
    /// Subdivisions per beat: 2 (simple metre) or 3 (compound).
    pub subdivisions: u8,
}

impl Meter {
    /// 2/4.
    pub const TWO_FOUR: Meter = Meter {
        beats_per_bar: 2,
        subdivisions: 2,
    };
    /// 3/4.
    pub const THREE_FOUR: Meter = Meter {
        beats_per_bar: 3,
        subdivisions: 2,
    };
    /// 4/4.
    pub const FOUR_FOUR: Meter = Meter {
        beats_per_bar: 4,
        subdivisions: 2,
    };
    /// 6/8 as two beats of three eighths.
    pub const SIX_EIGHT: Meter = Meter {
        beats_per_bar: 2,
        subdivisions: 3,
    };
}

/// A written time signature, e.g. 6/8, and the **notated beat** it implies: a quarter in
/// 2/4, 3/4, 4/4; a half in 2/2 and 3/2; a dotted quarter in 6/8, 9/8, 12/8 (compound
/// metres are counted in dotted beats); and one dotted quarter per bar in 3/8, whose beats
/// are therefore its downbeats. Other signatures (5/8, 7/8, 5/4) count their written unit.
///
/// ```
/// use performance::{Meter, TimeSignature};
/// let six_eight = TimeSignature::new(6, 8);
/// assert_eq!(six_eight.meter(), Meter::SIX_EIGHT);
/// assert_eq!(six_eight.beat_quarters(), 1.5);
/// assert_eq!(TimeSignature::new(3, 8).meter().beats_per_bar, 1);
/// assert_eq!(TimeSignature::new(2, 2).beat_quarters(), 2.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct TimeSignature {
    /// Upper figure.
    pub numerator: u8,
    /// Lower figure (a power of two).
    pub denominator: u8,
}

impl TimeSignature {
    /// `numerator`/`denominator`.
    pub const fn new(numerator: u8, denominator: u8) -> Self {
        Self {
            numerator,
            denominator,
        }
    }

    /// Whether the signature is valid: numerator 1..=32, denominator 1, 2, 4, 8, 16 or 32.
    pub fn is_valid(self) -> bool {
        (1..=32).contains(&self.numerator) && [1, 2, 4, 8, 16, 32].contains(&self.denominator)
    }

    /// Compound (6/8, 9/8, 12/8, 6/16, …) or 3/8: counted in dotted beats of three units.
    fn dotted(self) -> bool {
        self.denominator >= 8 && self.numerator.is_multiple_of(3)
    }

    /// Beats per bar and their subdivision at the notated level.
    pub fn meter(self) -> Meter {
        if self.dotted() {
            Meter {
                beats_per_bar: (self.numerator / 3).max(1),
                subdivisions: 3,
            }
        } else {
            Meter {
                beats_per_bar: self.numerator.max(1),
                subdivisions: 2,
            }
        }
    }

    /// Length of one notated beat in quarter notes.
    pub fn beat_quarters(self) -> f64 {
        let unit = 4.0 / f64::from(self.denominator.max(1));
        if self.dotted() {
            3.0 * unit
        } else {
            unit
        }
    }

    /// Length of a full bar in quarter notes.
    pub fn bar_quarters(self) -> f64 {
        f64::from(self.numerator) * 4.0 / f64::from(self.denominator.max(1))
    }
}

impl std::fmt::Display for TimeSignature {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.numerator, self.denominator)
    }
}

impl std::str::FromStr for TimeSignature {
    type Err = PerformanceError;

    /// Parses `N/D` (spaces around the figures allowed), e.g. `3/4`, `6/8`, `2/2`.
    ///
    /// ```
    /// use performance::TimeSignature;
    /// assert_eq!("6/8".parse::<TimeSignature>().unwrap(), TimeSignature::new(6, 8));
    /// assert!("3/5".parse::<TimeSignature>().is_err());
    /// assert!("waltz".parse::<TimeSignature>().is_err());
    /// ```
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || PerformanceError::TimeSignature(s.to_string());
        let (n, d) = s.split_once('/').ok_or_else(bad)?;
        let figure = |t: &str| t.trim().parse::<u8>().map_err(|_| bad());
        let ts = TimeSignature::new(figure(n)?, figure(d)?);
        if ts.is_valid() {
            Ok(ts)
        } else {
            Err(bad())
        }
    }
}
