//! Beats, downbeats, metre and tempo of a recording: beat-net's learned activation decoded
//! by `beat_track::bar_pointer` (the default), or the classic onset/dynamic-programming
//! tracker of `beat-track` ([`BeatMethod::Classic`]).

use beat_net::Activations;
use beat_track::bar_pointer::{self, BarPointerConfig};
use performance::{Meter, Note};

use crate::error::Result;

/// Which beat tracker the audio analysis uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BeatMethod {
    /// beat-net's activation + bar-pointer decoding (issue 20).
    #[default]
    Learned,
    /// The onset-strength tracker (tempogram, Ellis DP, accent metre) of `beat-track`.
    Classic,
}

impl std::str::FromStr for BeatMethod {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "learned" => Ok(Self::Learned),
            "classic" => Ok(Self::Classic),
            other => Err(format!(
                "unknown beat method \"{other}\": use learned or classic"
            )),
        }
    }
}

/// What either tracker found.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Beats {
    pub(crate) beats_s: Vec<f64>,
    pub(crate) downbeats_s: Vec<f64>,
    pub(crate) tempo_bpm: f64,
    pub(crate) meter: Option<Meter>,
    pub(crate) confidence: Option<f32>,
}

/// Log-bonus for a downbeat within a frame of a detected bow change: bars tend to start
/// with a new bow. It chooses where bars start, not how long they are
/// (`bar_pointer::decode_with_downbeat_evidence`). Chosen on the corpus's validation split
/// (`violin-skeleton evaluate --data corpus-hook --split val`, bonus 0 / 0.5 / 0.75 / 1 /
/// 1.25 / 1.5 / 2): downbeat F 0.715 / 0.723 / 0.729 / 0.728 / 0.726 / 0.722 / 0.698, stroke
/// direction 0.673 / 0.682 / 0.688 / 0.689 / 0.689 / 0.689 / 0.689. Weighting it by the
/// stroke network's down-bow output added nothing (0.725).
pub(crate) const BOW_CHANGE_DOWNBEAT_BONUS: f32 = 1.0;

/// The learned path: bar-pointer decoding of `act`, the bars phased on the bow changes;
/// compound or simple from the notes.
pub(crate) fn learned(act: &Activations, notes: &[Note], bow_changes_s: &[f64]) -> Result<Beats> {
    let cfg = BarPointerConfig::default();
    let frames = act.beat.len();
    let mut evidence = vec![0.0f32; frames];
    for &c in bow_changes_s {
        let f = (c * cfg.fps).round();
        if !(f.is_finite() && f >= 0.0) {
            continue;
        }
        let f = f as usize;
        for e in evidence.iter_mut().take(f + 2).skip(f.saturating_sub(1)) {
            *e = BOW_CHANGE_DOWNBEAT_BONUS;
        }
    }
    let decoded =
        bar_pointer::decode_with_downbeat_evidence(&act.beat, &act.downbeat, &evidence, &cfg)?;
    let onsets: Vec<f64> = notes.iter().map(|n| n.onset_s).collect();
    let meter = (!decoded.beats_s.is_empty()).then(|| Meter {
        beats_per_bar: decoded.beats_per_bar.min(usize::from(u8::MAX)) as u8,
        subdivisions: beat_track::subdivisions(&decoded.beats_s, &onsets),
    });
    Ok(Beats {
        beats_s: decoded.beats_s,
        downbeats_s: decoded.downbeats_s,
        tempo_bpm: decoded.tempo_bpm,
        meter,
        confidence: Some(decoded.confidence),
    })
}

/// The classic tracker on the analysis-rate samples; notes and bow changes are metre
/// evidence (bars tend to start with a new bow).
pub(crate) fn classic(samples: &[f32], notes: &[Note], bow_changes_s: &[f64]) -> Result<Beats> {
    let b = beat_track::BeatTracker::new(beat_track::BeatConfig::default())?.track_with(
        samples,
        beat_track::BarEvidence {
            notes: Some(notes),
            bow_changes_s: Some(bow_changes_s),
        },
    )?;
    Ok(Beats {
        beats_s: b.beats_s,
        downbeats_s: b.downbeats_s,
        tempo_bpm: b.tempo_bpm,
        meter: Some(b.meter),
        confidence: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn silence_gives_no_beats_and_no_metre() {
        let act = Activations {
            beat: vec![0.0; 900],
            downbeat: vec![0.0; 900],
        };
        let b = learned(&act, &[], &[1.0, 2.0]).unwrap();
        assert!(b.beats_s.is_empty() && b.meter.is_none());
        assert_eq!(b.confidence, Some(0.0));
        assert_eq!("classic".parse::<BeatMethod>(), Ok(BeatMethod::Classic));
        assert!("x".parse::<BeatMethod>().is_err());
    }
}
