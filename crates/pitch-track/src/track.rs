//! The tracker's output, [`PitchTrack`], and the tracker itself, [`PitchTracker`].

use performance::F0Track;
use serde::{Deserialize, Serialize};

use crate::config::PitchConfig;
use crate::error::{first_non_finite, PitchError, Result};
use crate::hmm::Hmm;
use crate::yin::{Observations, Yin};

/// An f0 track on a regular time grid: frame `t` is centred at `t · hop_s` seconds.
///
/// ```
/// use pitch_track::PitchTrack;
/// let track = PitchTrack { hop_s: 0.01, f0_hz: vec![f32::NAN, 440.0, 440.0], voiced_prob: vec![0.0, 0.9, 0.9] };
/// assert_eq!(track.voiced_count(), 2);
/// assert_eq!(track.midi(1), Some(69.0));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PitchTrack {
    /// Seconds between frames.
    pub hop_s: f64,
    /// Fundamental frequency per frame in Hz; NaN where the frame is unvoiced.
    pub f0_hz: Vec<f32>,
    /// Probability that the frame is voiced (pYIN's sum of candidate probabilities).
    pub voiced_prob: Vec<f32>,
}

impl PitchTrack {
    /// The track in `analysis.json`'s form ([`F0Track`]: 0 Hz where unvoiced, as JSON has
    /// no NaN).
    pub fn to_f0_track(&self) -> F0Track {
        F0Track {
            hop_s: self.hop_s,
            hz: self
                .f0_hz
                .iter()
                .map(|&f| if f.is_finite() { f } else { 0.0 })
                .collect(),
            voiced_prob: self.voiced_prob.clone(),
        }
    }

    /// A track from `analysis.json`'s form (0 Hz or less reads as unvoiced).
    ///
    /// ```
    /// let f0 = performance::F0Track { hop_s: 0.01, hz: vec![0.0, 440.0], voiced_prob: vec![0.1, 0.9] };
    /// let track = pitch_track::PitchTrack::from_f0_track(&f0);
    /// assert!(track.f0_hz[0].is_nan());
    /// assert_eq!(track.to_f0_track(), f0);
    /// ```
    pub fn from_f0_track(f0: &F0Track) -> PitchTrack {
        PitchTrack {
            hop_s: f0.hop_s,
            f0_hz: f0
                .hz
                .iter()
                .map(|&f| if f > 0.0 { f } else { f32::NAN })
                .collect(),
            voiced_prob: f0.voiced_prob.clone(),
        }
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.f0_hz.len()
    }

    /// `true` when there is no frame.
    pub fn is_empty(&self) -> bool {
        self.f0_hz.is_empty()
    }

    /// Number of voiced frames.
    pub fn voiced_count(&self) -> usize {
        self.f0_hz.iter().filter(|f| f.is_finite()).count()
    }

    /// Time of frame `t` in seconds.
    pub fn time_s(&self, t: usize) -> f64 {
        t as f64 * self.hop_s
    }

    /// Fractional MIDI pitch of frame `t` (`69 + 12 log2(f0 / 440)`), `None` when unvoiced.
    pub fn midi(&self, t: usize) -> Option<f32> {
        self.f0_hz
            .get(t)
            .filter(|f| f.is_finite() && **f > 0.0)
            .map(|f| hz_to_midi(*f))
    }

    /// The track on another frame rate (e.g. 30 fps for the skeleton). An output frame
    /// between two voiced input frames interpolates their pitch linearly in semitones; next
    /// to an unvoiced frame it takes the nearest input frame. `voiced_prob` is interpolated
    /// linearly. The output covers the same span: `floor(span · fps) + 1` frames.
    ///
    /// ```
    /// use pitch_track::PitchTrack;
    /// let t = PitchTrack { hop_s: 0.5, f0_hz: vec![220.0, 440.0, f32::NAN], voiced_prob: vec![1.0, 1.0, 0.0] };
    /// let r = t.resample_to_fps(4.0);
    /// assert_eq!(r.len(), 5);
    /// assert!((r.f0_hz[1] - 311.127).abs() < 0.01); // halfway in semitones
    /// assert!(r.f0_hz[4].is_nan());
    /// ```
    pub fn resample_to_fps(&self, fps: f64) -> PitchTrack {
        if self.is_empty() || !(fps.is_finite() && fps > 0.0) || self.hop_s <= 0.0 {
            return PitchTrack {
                hop_s: if fps > 0.0 { 1.0 / fps } else { self.hop_s },
                f0_hz: Vec::new(),
                voiced_prob: Vec::new(),
            };
        }
        let span_s = (self.len() - 1) as f64 * self.hop_s;
        let n_out = (span_s * fps + 1e-9).floor() as usize + 1;
        let mut f0_hz = Vec::with_capacity(n_out);
        let mut voiced_prob = Vec::with_capacity(n_out);
        let last = self.len() - 1;
        for k in 0..n_out {
            let pos = (k as f64 / fps / self.hop_s).min(last as f64);
            let i = (pos.floor() as usize).min(last);
            let j = (i + 1).min(last);
            let w = (pos - i as f64) as f32;
            let (a, b) = (self.f0_hz[i], self.f0_hz[j]);
            let f = if a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0 {
                midi_to_hz(hz_to_midi(a) * (1.0 - w) + hz_to_midi(b) * w)
            } else if w < 0.5 {
                a
            } else {
                b
            };
            f0_hz.push(f);
            voiced_prob.push(self.voiced_prob[i] * (1.0 - w) + self.voiced_prob[j] * w);
        }
        PitchTrack {
            hop_s: 1.0 / fps,
            f0_hz,
            voiced_prob,
        }
    }
}

/// Fractional MIDI pitch of a frequency.
pub fn hz_to_midi(hz: f32) -> f32 {
    69.0 + 12.0 * (hz / 440.0).log2()
}

/// Frequency of a fractional MIDI pitch.
pub fn midi_to_hz(midi: f32) -> f32 {
    440.0 * ((midi - 69.0) / 12.0).exp2()
}

/// A planned pYIN tracker: FFT plans, priors and the banded transition model are built once
/// by [`PitchTracker::new`] and reused by every [`PitchTracker::track`].
///
/// The f0 of a voiced frame is the exact frequency (parabolically refined YIN period) of the
/// most probable candidate within half a semitone of the decoded bin, or the bin's centre
/// when there is none; librosa returns the bin centre.
///
/// ```
/// use pitch_track::{PitchConfig, PitchTracker};
/// let sr = 22_050.0;
/// let tone: Vec<f32> = (0..22_050).map(|i| (2.0 * std::f32::consts::PI * 440.0 * i as f32 / sr).sin()).collect();
/// let track = PitchTracker::new(PitchConfig::default())?.track(&tone)?;
/// let mid = track.len() / 2;
/// assert!((track.f0_hz[mid] - 440.0).abs() < 1.0);
/// # Ok::<(), pitch_track::PitchError>(())
/// ```
pub struct PitchTracker {
    cfg: PitchConfig,
    yin: Yin,
    hmm: Hmm,
}

impl std::fmt::Debug for PitchTracker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PitchTracker")
            .field("cfg", &self.cfg)
            .finish_non_exhaustive()
    }
}

impl PitchTracker {
    /// Validates `cfg` and plans everything.
    pub fn new(cfg: PitchConfig) -> Result<Self> {
        cfg.validate()?;
        if cfg.n_pitch_bins() > usize::from(u16::MAX) / 2 {
            return Err(PitchError::InvalidConfig(format!(
                "{} pitch bins is too many; use a coarser resolution_semitones",
                cfg.n_pitch_bins()
            )));
        }
        Ok(Self {
            yin: Yin::new(&cfg),
            hmm: Hmm::new(&cfg),
            cfg,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &PitchConfig {
        &self.cfg
    }

    /// Tracks f0 in `samples` (mono, at `config().sample_rate_hz`): `1 + len / hop` frames.
    /// Empty input and NaN/infinite samples are errors; silence gives an all-unvoiced track.
    pub fn track(&self, samples: &[f32]) -> Result<PitchTrack> {
        if samples.is_empty() {
            return Err(PitchError::EmptyAudio);
        }
        if let Some(index) = first_non_finite(samples) {
            return Err(PitchError::NonFinite { index });
        }
        let obs = self.yin.observe(samples);
        let path = self.hmm.decode(&obs);
        Ok(PitchTrack {
            hop_s: self.cfg.hop_s(),
            f0_hz: self.frequencies(&obs, &path),
            voiced_prob: obs.voiced_prob,
        })
    }

    fn frequencies(&self, obs: &Observations, path: &[Option<usize>]) -> Vec<f32> {
        let bins_per_octave = 12.0 * self.cfg.bins_per_semitone() as f64;
        let reach = (self.cfg.bins_per_semitone() / 4) as i64;
        path.iter()
            .enumerate()
            .map(|(t, state)| match state {
                None => f32::NAN,
                Some(bin) => obs
                    .frame(t)
                    .iter()
                    .filter(|c| (i64::from(c.bin) - *bin as i64).abs() <= reach)
                    .max_by(|a, b| a.prob.total_cmp(&b.prob))
                    .map(|c| c.f0_hz)
                    .unwrap_or_else(|| {
                        (self.cfg.fmin_hz * (*bin as f64 / bins_per_octave).exp2()) as f32
                    }),
            })
            .collect()
    }
}
