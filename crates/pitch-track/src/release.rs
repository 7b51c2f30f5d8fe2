//! Where a note's sound was released: the bow stopped, and what follows is the room ringing.
//!
//! The pitch path keeps a note voiced for as long as it hears its pitch, and in a room that
//! includes the reverberation after the bow has stopped (on the corpus's validation items a
//! note before a rest or at the end ends a median 0.25 s late). A bowed note holds its level
//! while the bow drives the string and decays once it stops, so [`release_s`] finds the start
//! of the note's trailing stretch that stays [`ReleaseConfig::drop_db`] under the note's
//! sustained level. The facade uses it to tell where the music ends, so that no beat is
//! tracked in the ring and the silence after it.

use crate::error::{PitchError, Result};
use crate::Note;

/// Settings of [`release_s`].
#[derive(Debug, Clone, PartialEq)]
pub struct ReleaseConfig {
    /// How far under the note's sustained level (the 90th percentile of its frame levels)
    /// the level must stay, to the note's end, to count as released, dB.
    pub drop_db: f32,
    /// The release is never earlier than this after the note's onset, seconds.
    pub min_note_s: f64,
    /// Hop of the RMS level frames, seconds.
    pub hop_s: f64,
}

impl Default for ReleaseConfig {
    /// 6 dB, 0.07 s, 10 ms: the drop chosen on the corpus's validation split by the offsets
    /// of the notes before rests (median absolute error 0.319 s → 0.096 s;
    /// `crates/pitch-track/EXPERIMENTS.md`).
    fn default() -> Self {
        Self {
            drop_db: 6.0,
            min_note_s: 0.07,
            hop_s: 0.01,
        }
    }
}

impl ReleaseConfig {
    /// Checks that the settings are usable.
    pub fn validate(&self) -> Result<()> {
        let ok = self.drop_db.is_finite()
            && self.drop_db > 0.0
            && self.hop_s.is_finite()
            && self.hop_s > 0.0
            && self.min_note_s.is_finite()
            && self.min_note_s >= 0.0;
        if ok {
            Ok(())
        } else {
            Err(PitchError::InvalidConfig(format!(
                "release drop_db {} and hop_s {} must be > 0, min_note_s {} ≥ 0",
                self.drop_db, self.hop_s, self.min_note_s
            )))
        }
    }
}

/// The time (s) where `note`'s sound was released in `samples`: the start of its trailing
/// stretch whose level stays [`ReleaseConfig::drop_db`] under the note's sustained level, at
/// least [`ReleaseConfig::min_note_s`] after the onset. The note's offset when the level never
/// falls that far, or when the note lies outside the audio.
///
/// ```
/// use pitch_track::{release_s, Note, ReleaseConfig};
/// let sr = 8_000u32;
/// // 0.5 s of A4, then its ring decaying by 60 dB per second for 0.5 s.
/// let x: Vec<f32> = (0..sr as usize).map(|i| {
///     let t = i as f32 / sr as f32;
///     let gain = if t < 0.5 { 1.0 } else { 10f32.powf(-3.0 * (t - 0.5)) };
///     gain * (std::f32::consts::TAU * 440.0 * t).sin()
/// }).collect();
/// let released = release_s(&Note::new(0.0, 1.0, 69), &x, sr, &ReleaseConfig::default())?;
/// assert!((released - 0.6).abs() < 0.05, "{released}");
/// # Ok::<(), pitch_track::PitchError>(())
/// ```
pub fn release_s(
    note: &Note,
    samples: &[f32],
    sample_rate_hz: u32,
    cfg: &ReleaseConfig,
) -> Result<f64> {
    cfg.validate()?;
    let hop = (cfg.hop_s * f64::from(sample_rate_hz)).round() as usize;
    if hop == 0 || samples.is_empty() || !(note.onset_s.is_finite() && note.offset_s.is_finite()) {
        return Ok(note.offset_s);
    }
    let hop_s = hop as f64 / f64::from(sample_rate_hz);
    let frames = samples.len().div_ceil(hop);
    let frame = |t: f64| ((t / hop_s).floor().max(0.0) as usize).min(frames);
    let (a, b) = (frame(note.onset_s), frame(note.offset_s));
    let keep = frame(note.onset_s + cfg.min_note_s).max(a + 1);
    if b <= keep {
        return Ok(note.offset_s);
    }
    // Mean power of each frame (non-finite samples count as 0), in dB with a −120 dB floor.
    let mut level: Vec<f32> = samples[a * hop..(b * hop).min(samples.len())]
        .chunks(hop)
        .map(|frame| {
            let energy: f64 = frame
                .iter()
                .map(|&v| {
                    if v.is_finite() {
                        f64::from(v).powi(2)
                    } else {
                        0.0
                    }
                })
                .sum();
            (energy / frame.len() as f64) as f32
        })
        .collect();
    let db = dsp_mel::DbConfig {
        reference: dsp_mel::DbRef::Value(1.0),
        amin: 1e-12,
        top_db: None,
    };
    dsp_mel::power_to_db(&mut level, &db);
    let mut sorted = level.clone();
    sorted.sort_by(f32::total_cmp);
    let sustained = sorted[(sorted.len() * 9 / 10).min(sorted.len() - 1)];
    let quiet = sustained - cfg.drop_db;
    let mut j = b;
    while j > keep && level[j - 1 - a] < quiet {
        j -= 1;
    }
    Ok(if j < b {
        (j as f64 * hop_s).clamp(note.onset_s, note.offset_s)
    } else {
        note.offset_s
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SR: u32 = 8_000;

    /// `hold_s` of a sine at full level, then a ring decaying at `db_per_s`, `total_s` long.
    fn ring(hold_s: f32, db_per_s: f32, total_s: f32) -> Vec<f32> {
        (0..(total_s * SR as f32) as usize)
            .map(|i| {
                let t = i as f32 / SR as f32;
                let db = if t < hold_s {
                    0.0
                } else {
                    -db_per_s * (t - hold_s)
                };
                10f32.powf(db / 20.0) * (std::f32::consts::TAU * 440.0 * t).sin()
            })
            .collect()
    }

    #[test]
    fn the_release_is_where_the_ring_starts() {
        let x = ring(0.6, 60.0, 1.5);
        let r = release_s(&Note::new(0.0, 1.4, 69), &x, SR, &ReleaseConfig::default()).unwrap();
        // 6 dB under the sustained level is reached 0.1 s into a 60 dB/s ring.
        assert!((r - 0.7).abs() < 0.03, "{r}");
    }

    #[test]
    fn a_sustained_note_keeps_its_end() {
        let x = ring(2.0, 60.0, 2.0);
        let note = Note::new(0.5, 1.5, 69);
        assert_eq!(
            release_s(&note, &x, SR, &ReleaseConfig::default()).unwrap(),
            1.5
        );
    }

    #[test]
    fn a_note_in_silence_keeps_its_minimum_length() {
        let note = Note::new(0.2, 0.9, 69);
        let r = release_s(
            &note,
            &vec![0.0; SR as usize],
            SR,
            &ReleaseConfig::default(),
        )
        .unwrap();
        assert!((0.2 + 0.07 - 0.011..=0.9).contains(&r), "{r}");
    }

    #[test]
    fn bad_input_is_refused_or_left_alone() {
        let note = Note::new(0.0, 1.0, 69);
        let bad = ReleaseConfig {
            drop_db: f32::NAN,
            ..ReleaseConfig::default()
        };
        assert!(release_s(&note, &[0.0; 100], SR, &bad).is_err());
        // No audio, NaN samples, a note past the end of the audio, a NaN note: no panic.
        let cfg = ReleaseConfig::default();
        assert_eq!(release_s(&note, &[], SR, &cfg).unwrap(), 1.0);
        let r = release_s(&note, &[f32::NAN; 400], SR, &cfg).unwrap();
        assert!((0.0..=1.0).contains(&r), "{r}");
        let late = Note::new(5.0, 6.0, 69);
        assert_eq!(release_s(&late, &[0.1; 400], SR, &cfg).unwrap(), 6.0);
        let nan = Note {
            offset_s: f64::NAN,
            ..note
        };
        assert!(release_s(&nan, &[0.1; 400], SR, &cfg).unwrap().is_nan());
    }
}
