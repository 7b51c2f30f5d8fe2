//! Note segmentation: from an f0 track (and an onset novelty curve) to [`Note`]s.
//!
//! The method is documented at [`segment_notes`].

pub use performance::Note;

use crate::error::{PitchError, Result};
use crate::note_config::NoteConfig;
use crate::novelty::onset_novelty;
use crate::track::PitchTrack;

/// Segments `track` into notes, computing the onset novelty from `samples` (the audio the
/// track came from, at `sample_rate_hz`).
///
/// The method, in order:
/// 1. **Voiced runs.** Frames with an f0 form runs; unvoiced gaps shorter than
///    [`NoteConfig::max_gap_s`] are bridged (pYIN drops a frame or two at bow noise).
/// 2. **Stable pitch.** Inside a run, the pitch in semitones is median-filtered over
///    [`NoteConfig::smooth_s`] (about one vibrato cycle, so ±50-cent vibrato at 5–7 Hz
///    averages out) and quantised to semitones with hysteresis
///    ([`NoteConfig::hysteresis_semitones`]); a change point is moved back to where the
///    smoothed pitch crossed the midpoint between the two semitones.
/// 3. **No glide notes.** A segment shorter than [`NoteConfig::min_note_s`] (the semitones
///    a slurred glide passes through, a blip) is given to its neighbours: split at its
///    middle when it lies between them in pitch, otherwise merged into the neighbour
///    closest in pitch; a run that is only such a blip is dropped. Neighbours left with the
///    same pitch are joined.
/// 4. **Pitch of a note** = the rounded median of its raw frame pitches (the vibrato centre).
/// 5. **Repeated notes.** A segment is split at every onset-novelty peak inside it (at least
///    `min_note_s` from either end) that stands [`NoteConfig::onset_delta_db`] above the local
///    mean and reaches [`NoteConfig::onset_floor_db`]: bow changes on the same pitch. The
///    novelty is a mean rise in dB per band, so fixed thresholds do not depend on the
///    recording's level (a re-attack rises by 3–10 dB, vibrato by well under 1 dB).
/// 6. **Attacks.** pYIN declares voicing a little after a note starts from silence; the
///    first note of a run moves back to a novelty peak within [`NoteConfig::onset_snap_s`].
/// 7. **Latency.** Every onset and offset moves [`NoteConfig::latency_s`] earlier: change
///    points found on the pitch path lag the start of the change (median +14 to +21 ms on
///    the labelled corpus, in both renderers and for slurred and re-bowed changes alike).
///
/// ```
/// use pitch_track::{segment_notes, NoteConfig, PitchConfig, PitchTracker};
/// let sr = 22_050u32;
/// // A4 for 0.5 s then C5 for 0.5 s.
/// let x: Vec<f32> = (0..sr as usize).map(|i| {
///     let f = if i < sr as usize / 2 { 440.0 } else { 523.25 };
///     (2.0 * std::f32::consts::PI * f * i as f32 / sr as f32).sin()
/// }).collect();
/// let track = PitchTracker::new(PitchConfig::default())?.track(&x)?;
/// let notes = segment_notes(&track, &x, sr, &NoteConfig::default())?;
/// assert_eq!(notes.iter().map(|n| n.midi).collect::<Vec<_>>(), vec![69, 72]);
/// # Ok::<(), pitch_track::PitchError>(())
/// ```
pub fn segment_notes(
    track: &PitchTrack,
    samples: &[f32],
    sample_rate_hz: u32,
    cfg: &NoteConfig,
) -> Result<Vec<Note>> {
    let hop = (track.hop_s * f64::from(sample_rate_hz)).round() as usize;
    if hop == 0 {
        return Err(PitchError::InvalidConfig(format!(
            "track hop {} s is below one sample at {sample_rate_hz} Hz",
            track.hop_s
        )));
    }
    let mut novelty = onset_novelty(samples, sample_rate_hz, hop, &cfg.novelty)?;
    novelty.resize(track.len(), 0.0);
    segment_notes_with_novelty(track, &novelty, cfg)
}

/// Segments `track` into notes with a precomputed novelty curve on the track's frames
/// (in dB, as [`onset_novelty`] computes it).
pub fn segment_notes_with_novelty(
    track: &PitchTrack,
    novelty: &[f32],
    cfg: &NoteConfig,
) -> Result<Vec<Note>> {
    if novelty.len() != track.len() {
        return Err(PitchError::LengthMismatch {
            what: "novelty vs pitch track",
            left: novelty.len(),
            right: track.len(),
        });
    }
    if !(track.hop_s.is_finite() && track.hop_s > 0.0) {
        return Err(PitchError::InvalidConfig(format!(
            "track hop_s must be > 0, got {}",
            track.hop_s
        )));
    }
    if !(cfg.latency_s.is_finite() && cfg.latency_s >= 0.0) {
        return Err(PitchError::InvalidConfig(format!(
            "latency_s must be a finite number ≥ 0 s, got {}",
            cfg.latency_s
        )));
    }
    let frames = |s: f64| ((s / track.hop_s).round() as usize).max(1);
    let min_len = frames(cfg.min_note_s);
    let midi: Vec<Option<f32>> = (0..track.len()).map(|t| track.midi(t)).collect();
    let peaks = novelty_peaks(novelty, cfg, track.hop_s);
    let mut notes = Vec::new();
    for (start, end) in voiced_runs(&midi, frames(cfg.max_gap_s)) {
        let pitch = bridged(&midi[start..end]);
        let smooth = median_filter(&pitch, frames(cfg.smooth_s) / 2);
        let mut segs = quantise(&smooth, cfg.hysteresis_semitones);
        absorb_short(&mut segs, min_len);
        for seg in segs.iter_mut() {
            seg.pitch = median_pitch(&midi[start + seg.start..start + seg.end]);
        }
        join_equal(&mut segs);
        let mut first = true;
        for seg in &segs {
            let (mut a, b) = (start + seg.start, start + seg.end);
            if first {
                let snap = frames(cfg.onset_snap_s);
                if let Some(&p) = peaks.iter().rev().find(|&&p| p <= a && p + snap >= a) {
                    a = p;
                }
                first = false;
            }
            let mut from = a;
            for &p in peaks
                .iter()
                .filter(|&&p| p >= a + min_len && p + min_len <= b)
            {
                if p >= from + min_len {
                    notes.push(note(from, p, seg.pitch, track.hop_s));
                    from = p;
                }
            }
            notes.push(note(from, b, seg.pitch, track.hop_s));
        }
    }
    for n in &mut notes {
        n.onset_s = (n.onset_s - cfg.latency_s).max(0.0);
        n.offset_s = (n.offset_s - cfg.latency_s).max(n.onset_s);
    }
    Ok(notes)
}

fn note(start: usize, end: usize, pitch: f32, hop_s: f64) -> Note {
    Note::new(
        start as f64 * hop_s,
        end as f64 * hop_s,
        pitch.round().clamp(0.0, 127.0) as u8,
    )
}

/// A stretch of constant quantised pitch, frames `start..end` of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Segment {
    start: usize,
    end: usize,
    pitch: f32,
}

impl Segment {
    fn len(&self) -> usize {
        self.end - self.start
    }
}

/// Runs of voiced frames, bridging unvoiced gaps of at most `max_gap` frames.
fn voiced_runs(midi: &[Option<f32>], max_gap: usize) -> Vec<(usize, usize)> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut t = 0;
    while t < midi.len() {
        if midi[t].is_none() {
            t += 1;
            continue;
        }
        let start = t;
        while t < midi.len() && midi[t].is_some() {
            t += 1;
        }
        match runs.last_mut() {
            Some(last) if start - last.1 <= max_gap => last.1 = t,
            _ => runs.push((start, t)),
        }
    }
    runs
}

/// The run's pitch with bridged gaps filled by the last voiced value.
fn bridged(midi: &[Option<f32>]) -> Vec<f32> {
    let mut last = midi.iter().flatten().next().copied().unwrap_or(0.0);
    midi.iter()
        .map(|m| {
            if let Some(v) = m {
                last = *v;
            }
            last
        })
        .collect()
}

/// Running median over `t − half ..= t + half`, clipped to the signal.
fn median_filter(x: &[f32], half: usize) -> Vec<f32> {
    let mut window = Vec::with_capacity(2 * half + 1);
    (0..x.len())
        .map(|t| {
            window.clear();
            window.extend_from_slice(&x[t.saturating_sub(half)..(t + half + 1).min(x.len())]);
            window.sort_by(f32::total_cmp);
            window[window.len() / 2]
        })
        .collect()
}

/// Semitone segments of a smoothed pitch, with hysteresis and midpoint change points.
fn quantise(smooth: &[f32], hysteresis: f32) -> Vec<Segment> {
    let mut segs: Vec<Segment> = Vec::new();
    let Some(&first) = smooth.first() else {
        return segs;
    };
    let mut current = first.round();
    let mut start = 0;
    for (t, &s) in smooth.iter().enumerate() {
        if (s - current).abs() <= 0.5 + hysteresis {
            continue;
        }
        let next = s.round();
        let mid = 0.5 * (current + next);
        let rising = next > current;
        let mut cut = t;
        while cut > start + 1 && (smooth[cut - 1] > mid) == rising {
            cut -= 1;
        }
        segs.push(Segment {
            start,
            end: cut,
            pitch: current,
        });
        start = cut;
        current = next;
    }
    segs.push(Segment {
        start,
        end: smooth.len(),
        pitch: current,
    });
    segs
}

/// Gives every segment shorter than `min_len` to its neighbours (step 3 of [`segment_notes`]).
fn absorb_short(segs: &mut Vec<Segment>, min_len: usize) {
    loop {
        let Some(i) = (0..segs.len())
            .filter(|&i| segs[i].len() < min_len)
            .min_by_key(|&i| segs[i].len())
        else {
            return;
        };
        let s = segs[i];
        let prev = i.checked_sub(1).map(|j| segs[j]);
        let next = segs.get(i + 1).copied();
        match (prev, next) {
            (None, None) => {
                segs.clear();
                return;
            }
            (Some(p), Some(n)) if (p.pitch - s.pitch) * (n.pitch - s.pitch) < 0.0 => {
                let mid = s.start + s.len() / 2;
                segs[i - 1].end = mid;
                segs[i + 1].start = mid;
                segs.remove(i);
            }
            (Some(p), n)
                if n.is_none_or(|n| (p.pitch - s.pitch).abs() <= (n.pitch - s.pitch).abs()) =>
            {
                segs[i - 1].end = s.end;
                segs.remove(i);
            }
            _ => {
                segs[i + 1].start = s.start;
                segs.remove(i);
            }
        }
        join_equal(segs);
    }
}

/// Joins neighbouring segments of equal pitch.
fn join_equal(segs: &mut Vec<Segment>) {
    let mut i = 1;
    while i < segs.len() {
        if segs[i].pitch == segs[i - 1].pitch {
            segs[i - 1].end = segs[i].end;
            segs.remove(i);
        } else {
            i += 1;
        }
    }
}

/// The rounded median of the voiced frames' pitches.
fn median_pitch(midi: &[Option<f32>]) -> f32 {
    let mut v: Vec<f32> = midi.iter().flatten().copied().collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f32::total_cmp);
    v[v.len() / 2].round()
}

/// Frames of novelty peaks: local maxima over ±window that reach `onset_floor_db` and stand
/// `onset_delta_db` above the local mean.
fn novelty_peaks(x: &[f32], cfg: &NoteConfig, hop_s: f64) -> Vec<usize> {
    let w = ((cfg.onset_window_s / hop_s).round() as usize).max(1);
    let mut peaks = Vec::new();
    for t in 0..x.len() {
        if x[t] < cfg.onset_floor_db {
            continue;
        }
        let (lo, hi) = (t.saturating_sub(w), (t + w + 1).min(x.len()));
        let window = &x[lo..hi];
        let is_max = window.iter().all(|&v| v <= x[t]) && (lo..t).all(|k| x[k] < x[t]);
        if !is_max {
            continue;
        }
        let mean = window.iter().sum::<f32>() / window.len() as f32;
        if x[t] >= mean + cfg.onset_delta_db {
            peaks.push(t);
        }
    }
    peaks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantise_ignores_vibrato_and_finds_steps() {
        let x: Vec<f32> = (0..200)
            .map(|t| if t < 100 { 69.0 } else { 71.0 } + 0.1 * (t as f32 * 0.5).sin())
            .collect();
        let segs = quantise(&x, 0.2);
        assert_eq!(segs.len(), 2);
        assert_eq!((segs[0].end, segs[1].pitch), (100, 71.0));
    }

    #[test]
    fn glide_notes_are_absorbed() {
        let mut segs = vec![
            Segment {
                start: 0,
                end: 40,
                pitch: 60.0,
            },
            Segment {
                start: 40,
                end: 43,
                pitch: 61.0,
            },
            Segment {
                start: 43,
                end: 90,
                pitch: 62.0,
            },
        ];
        absorb_short(&mut segs, 6);
        assert_eq!(segs.len(), 2);
        assert_eq!(segs[0].end, 41);
        let mut blip = vec![Segment {
            start: 0,
            end: 3,
            pitch: 60.0,
        }];
        absorb_short(&mut blip, 6);
        assert!(blip.is_empty());
    }

    #[test]
    fn runs_bridge_short_gaps() {
        let m = [Some(1.0), None, Some(1.0), None, None, None, Some(2.0)];
        assert_eq!(voiced_runs(&m, 1), vec![(0, 3), (6, 7)]);
    }

    #[test]
    fn latency_moves_notes_earlier_and_must_be_valid() {
        let track = PitchTrack {
            hop_s: 0.01,
            f0_hz: vec![440.0; 100],
            voiced_prob: vec![1.0; 100],
        };
        let novelty = vec![0.0; 100];
        let cfg = NoteConfig {
            latency_s: 0.0,
            ..NoteConfig::default()
        };
        let plain = segment_notes_with_novelty(&track, &novelty, &cfg).unwrap();
        let shifted = segment_notes_with_novelty(
            &track,
            &novelty,
            &NoteConfig {
                latency_s: 0.02,
                ..cfg.clone()
            },
        )
        .unwrap();
        assert_eq!(plain.len(), 1);
        assert!((plain[0].offset_s - shifted[0].offset_s - 0.02).abs() < 1e-9);
        assert_eq!(shifted[0].onset_s, 0.0);
        for bad in [-0.01, f64::NAN] {
            let bad_cfg = NoteConfig {
                latency_s: bad,
                ..cfg.clone()
            };
            assert!(matches!(
                segment_notes_with_novelty(&track, &novelty, &bad_cfg),
                Err(PitchError::InvalidConfig(_))
            ));
        }
    }

    #[test]
    fn length_mismatch_is_an_error() {
        let track = PitchTrack {
            hop_s: 0.01,
            f0_hz: vec![440.0; 10],
            voiced_prob: vec![1.0; 10],
        };
        assert!(matches!(
            segment_notes_with_novelty(&track, &[0.0; 3], &NoteConfig::default()),
            Err(PitchError::LengthMismatch { .. })
        ));
    }
}
