//! The pitch reference of a played [`Timeline`] on a frame grid, for scoring f0 trackers on
//! the corpus's audio (the trackers' tests, benches and comparison scripts).
//!
//! The labels hold each note's nominal pitch; the renderers add vibrato (within ±25 cents),
//! 25 ms slur glides, attacks and release tails. Frames the labels cannot decide are left
//! out: within [`EDGE_S`] of a note's onset or offset, and from an offset to [`TAIL_S`] after
//! it unless another note sounds — the rule of `scripts/compare_analysis_librosa.py` and of
//! `violin-train`'s corpus evaluation.

use performance::Timeline;

/// Frames this close to a labelled note onset or offset are not scored (attacks, releases
/// and slur glides of about 25 ms).
pub const EDGE_S: f64 = 0.03;
/// Nor is the release tail after a note that no other note follows this soon (the corpus
/// does not label it).
pub const TAIL_S: f64 = 0.2;

fn midi_to_hz(midi: f64) -> f64 {
    440.0 * 2f64.powf((midi - 69.0) / 12.0)
}

/// The reference f0 of `timeline` at the times `k · hop_s`, `k < n_frames`: `Some(hz)` inside
/// a note (its MIDI pitch shifted by `tuning_cents`), `Some(0.0)` where nothing sounds and
/// `None` where the labels cannot decide (see the module's documentation). A `hop_s` that is
/// not positive and finite gives `None` everywhere.
///
/// ```
/// use corpus::item::{make_item, RendererKind};
/// use corpus::reference::reference_f0;
/// use corpus::render::BowedStringSynth;
/// let item = make_item(5, &Default::default(), &BowedStringSynth::default(), RendererKind::Builtin, false)?;
/// let hop_s = 256.0 / 22_050.0;
/// let f0 = reference_f0(&item.timeline, 0.0, hop_s, 1 + item.audio.len() / 256);
/// assert!(f0.iter().any(|f| f.is_some_and(|hz| hz > 0.0)));
/// # Ok::<(), corpus::CorpusError>(())
/// ```
pub fn reference_f0(
    timeline: &Timeline,
    tuning_cents: f64,
    hop_s: f64,
    n_frames: usize,
) -> Vec<Option<f32>> {
    if !(hop_s.is_finite() && hop_s > 0.0) {
        return vec![None; n_frames];
    }
    // Frames k with a <= k · hop_s < b.
    let frames = |a: f64, b: f64| {
        let lo = (a / hop_s).ceil().clamp(0.0, n_frames as f64) as usize;
        let hi = (b / hop_s).ceil().clamp(0.0, n_frames as f64) as usize;
        lo..hi.max(lo)
    };
    let notes: Vec<(f64, f64, f32)> = timeline
        .notes
        .iter()
        .map(|n| {
            let hz = midi_to_hz(f64::from(n.note.midi) + tuning_cents / 100.0);
            (n.note.onset_s, n.note.offset_s, hz as f32)
        })
        .collect();
    let mut reference = vec![0.0f32; n_frames];
    let mut keep = vec![true; n_frames];
    let mut sounding = vec![false; n_frames];
    for &(on, off, _) in &notes {
        for k in frames(on - EDGE_S, off + EDGE_S) {
            sounding[k] = true;
        }
    }
    for &(on, off, hz) in &notes {
        for k in frames(on + EDGE_S, off - EDGE_S) {
            reference[k] = hz;
        }
        for k in frames(on - EDGE_S, on + EDGE_S).chain(frames(off - EDGE_S, off + EDGE_S)) {
            keep[k] = false;
        }
        for k in frames(off, off + TAIL_S) {
            if !sounding[k] {
                keep[k] = false;
            }
        }
    }
    reference
        .into_iter()
        .zip(keep)
        .map(|(hz, keep)| keep.then_some(hz))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use performance::{Note, TimedNote};

    fn timed(on: f64, off: f64, midi: u8) -> TimedNote {
        TimedNote {
            note: Note::new(on, off, midi),
            bow_change: true,
            dynamic: 0.5,
            accent: false,
        }
    }

    #[test]
    fn notes_edges_tails_and_silence() {
        let timeline = Timeline {
            duration_s: 2.0,
            notes: vec![timed(0.5, 1.0, 69), timed(1.0, 1.2, 81)],
            beats_s: vec![],
            downbeats_s: vec![],
            arousal_2hz: vec![],
            tempo_bpm: 120.0,
        };
        let f0 = reference_f0(&timeline, 0.0, 0.01, 200);
        assert_eq!(f0[10], Some(0.0)); // silence before
        assert_eq!(f0[48], None); // onset edge
        assert_eq!(f0[70], Some(440.0));
        assert_eq!(f0[100], None); // the change between the notes
        assert!(f0[110].is_some_and(|hz| (hz - 880.0).abs() < 1e-3));
        assert_eq!(f0[130], None); // release tail
        assert_eq!(f0[150], Some(0.0));
        let sharp = reference_f0(&timeline, 100.0, 0.01, 200);
        assert!(sharp[70].is_some_and(|hz| (hz - 466.164).abs() < 1e-2));
        assert!(reference_f0(&timeline, 0.0, 0.0, 3)
            .iter()
            .all(Option::is_none));
    }
}
