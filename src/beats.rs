//! Beats, downbeats, metre and tempo of a recording: beat-net's learned activation decoded
//! by `beat_track::bar_pointer` (the default), or the classic onset/dynamic-programming
//! tracker of `beat-track` ([`BeatMethod::Classic`]); neither keeps a beat after the music's
//! release ([`AFTER_MUSIC_END_S`]).

use beat_net::Activations;
use beat_track::bar_pointer::{self, BarPointerConfig};
use performance::{Meter, Note, TimeSignature};

use crate::error::{Error, Result};

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

/// What the user knows about a recording's beat, for the learned tracker: the written time
/// signature (then the bar length is not guessed, and simple or compound comes from it) and
/// the tempo range at its notated beat (a quarter in 3/4, a dotted quarter in 6/8). Without
/// them the tracker guesses both, and on unseen music it most often misses exactly these: a
/// 4/4 read as 2/4, a tempo at double or half (`README.md`, "What limits the figures").
///
/// ```
/// use violin_skeleton::{BeatHints, Pipeline};
/// let hints = BeatHints {
///     time_signature: Some("3/4".parse()?),
///     tempo_range_bpm: Some((100.0, 140.0)),
/// };
/// hints.check()?;
/// let pipeline = Pipeline::builder().beat_hints(hints).build();
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BeatHints {
    /// The written time signature.
    pub time_signature: Option<TimeSignature>,
    /// Slowest and fastest tempo at the notated beat, bpm.
    pub tempo_range_bpm: Option<(f64, f64)>,
}

/// Tempo hints must lie within this range (bpm at the notated beat).
pub const HINT_TEMPO_RANGE_BPM: (f64, f64) = (10.0, 400.0);

/// Most beats per bar a time-signature hint may ask for (a 12/4 bar).
pub const HINT_MAX_BEATS_PER_BAR: u8 = 12;

/// How far either side of a single tempo (rather than a range) a hint reaches: the CLI's
/// `--tempo-bpm 120`, Python's `tempo_bpm=120`, `evaluate --hints tempo`.
pub const HINT_SINGLE_TEMPO_TOLERANCE: f64 = 0.15;

/// The tempo range of a single-tempo hint: `bpm` ÷ and × (1 + [`HINT_SINGLE_TEMPO_TOLERANCE`]).
///
/// ```
/// let (lo, hi) = violin_skeleton::hint_tempo_range_around(115.0);
/// assert!((lo - 100.0).abs() < 1e-9 && (hi - 132.25).abs() < 1e-9);
/// ```
pub fn hint_tempo_range_around(bpm: f64) -> (f64, f64) {
    let k = 1.0 + HINT_SINGLE_TEMPO_TOLERANCE;
    (bpm / k, bpm * k)
}

impl BeatHints {
    /// Whether any hint is given.
    pub fn is_empty(&self) -> bool {
        self.time_signature.is_none() && self.tempo_range_bpm.is_none()
    }

    /// Refuses hints the tracker cannot follow: an invalid time signature or one of more
    /// than [`HINT_MAX_BEATS_PER_BAR`] beats, and a tempo range that is not increasing
    /// within [`HINT_TEMPO_RANGE_BPM`].
    pub fn check(&self) -> Result<()> {
        if let Some(ts) = self.time_signature {
            if !ts.is_valid() || ts.meter().beats_per_bar > HINT_MAX_BEATS_PER_BAR {
                return Err(Error::BeatHint(format!(
                    "time signature {ts}: give one of at most {HINT_MAX_BEATS_PER_BAR} beats per bar, e.g. 3/4 or 6/8"
                )));
            }
        }
        if let Some((lo, hi)) = self.tempo_range_bpm {
            let (min, max) = HINT_TEMPO_RANGE_BPM;
            if !(lo.is_finite() && hi.is_finite() && min <= lo && lo < hi && hi <= max) {
                return Err(Error::BeatHint(format!(
                    "tempo range {lo}–{hi} bpm: give a slowest tempo below the fastest, both within {min}–{max} bpm"
                )));
            }
        }
        Ok(())
    }

    /// [`BeatHints::check`], and refuses any hint for a tracker that does not take them
    /// (the classic one).
    pub fn check_for(&self, method: BeatMethod) -> Result<()> {
        if method == BeatMethod::Classic && !self.is_empty() {
            return Err(Error::BeatHint(
                "time-signature and tempo hints need the learned beat tracker (the default): drop the classic one or the hints"
                    .into(),
            ));
        }
        self.check()
    }

    /// The decoder settings with the hints applied.
    fn decoder_config(&self) -> BarPointerConfig {
        let mut cfg = BarPointerConfig::default();
        if let Some(ts) = self.time_signature {
            cfg.beats_per_bar = vec![usize::from(ts.meter().beats_per_bar)];
            cfg.bar_length_prior_per_frame = Vec::new();
        }
        if let Some((lo, hi)) = self.tempo_range_bpm {
            cfg.min_bpm = lo;
            cfg.max_bpm = hi;
        }
        cfg
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

/// Beats and downbeats later than this after the music has ended ([`music_end_s`]) are
/// dropped, by both trackers. Chosen on the corpus's validation split (rules R65 and R70,
/// `crates/beat-track/EXPERIMENTS.md`).
pub(crate) const AFTER_MUSIC_END_S: f64 = 0.1;

/// Where the music ends: the release of the note that ends last
/// ([`pitch_track::release_s`]: where its level fell for good, not where the room stopped
/// ringing). `None` without notes.
pub(crate) fn music_end_s(
    notes: &[Note],
    samples: &[f32],
    sample_rate_hz: u32,
) -> Result<Option<f64>> {
    let Some(last) = notes
        .iter()
        .filter(|n| n.offset_s.is_finite())
        .max_by(|a, b| a.offset_s.total_cmp(&b.offset_s))
    else {
        return Ok(None);
    };
    let cfg = pitch_track::ReleaseConfig::default();
    Ok(Some(pitch_track::release_s(
        last,
        samples,
        sample_rate_hz,
        &cfg,
    )?))
}

/// The learned path: bar-pointer decoding of `act`, the bars phased on the bow changes;
/// compound or simple from the notes; no beat later than [`AFTER_MUSIC_END_S`] after
/// `end_s`, where the music ends ([`music_end_s`], when known).
pub(crate) fn learned(
    act: &Activations,
    notes: &[Note],
    bow_changes_s: &[f64],
    end_s: Option<f64>,
    hints: &BeatHints,
) -> Result<Beats> {
    hints.check()?;
    let cfg = hints.decoder_config();
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
    let mut decoded =
        bar_pointer::decode_with_downbeat_evidence(&act.beat, &act.downbeat, &evidence, &cfg)?;
    trim_after(end_s, &mut decoded.beats_s, &mut decoded.downbeats_s);
    if decoded.beats_s.is_empty() {
        // No beat (silence, or music too short to hold one): no tempo, no confidence.
        decoded.tempo_bpm = 0.0;
        decoded.confidence = 0.0;
    }
    let onsets: Vec<f64> = notes.iter().map(|n| n.onset_s).collect();
    let meter = (!decoded.beats_s.is_empty()).then(|| match hints.time_signature {
        Some(ts) => ts.meter(),
        None => Meter {
            beats_per_bar: decoded.beats_per_bar.min(usize::from(u8::MAX)) as u8,
            subdivisions: beat_track::subdivisions(&decoded.beats_s, &onsets),
        },
    });
    Ok(Beats {
        beats_s: decoded.beats_s,
        downbeats_s: decoded.downbeats_s,
        tempo_bpm: decoded.tempo_bpm,
        meter,
        confidence: Some(decoded.confidence),
    })
}

/// Drops the beats and downbeats later than [`AFTER_MUSIC_END_S`] after `end_s` (a finite
/// end only).
fn trim_after(end_s: Option<f64>, beats_s: &mut Vec<f64>, downbeats_s: &mut Vec<f64>) {
    if let Some(end) = end_s.filter(|e| e.is_finite()) {
        let last = end + AFTER_MUSIC_END_S;
        beats_s.retain(|&t| t <= last);
        downbeats_s.retain(|&t| t <= last);
    }
}

/// The classic tracker on the analysis-rate samples; notes and bow changes are metre
/// evidence (bars tend to start with a new bow); no beat later than [`AFTER_MUSIC_END_S`]
/// after `end_s`, as on the learned path.
pub(crate) fn classic(
    samples: &[f32],
    notes: &[Note],
    bow_changes_s: &[f64],
    end_s: Option<f64>,
) -> Result<Beats> {
    let b = beat_track::BeatTracker::new(beat_track::BeatConfig::default())?.track_with(
        samples,
        beat_track::BarEvidence {
            notes: Some(notes),
            bow_changes_s: Some(bow_changes_s),
        },
    )?;
    let (mut beats_s, mut downbeats_s, mut tempo_bpm) = (b.beats_s, b.downbeats_s, b.tempo_bpm);
    trim_after(end_s, &mut beats_s, &mut downbeats_s);
    if beats_s.is_empty() {
        // As on the learned path: no beat, no tempo.
        tempo_bpm = 0.0;
    }
    Ok(Beats {
        meter: (!beats_s.is_empty()).then_some(b.meter),
        beats_s,
        downbeats_s,
        tempo_bpm,
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
        let b = learned(&act, &[], &[1.0, 2.0], None, &BeatHints::default()).unwrap();
        assert!(b.beats_s.is_empty() && b.meter.is_none());
        assert_eq!(b.confidence, Some(0.0));
        assert_eq!("classic".parse::<BeatMethod>(), Ok(BeatMethod::Classic));
        assert!("x".parse::<BeatMethod>().is_err());
    }

    #[test]
    fn no_beat_is_kept_after_the_music_ends() {
        let act = ambiguous();
        let all = learned(&act, &[], &[], None, &BeatHints::default()).unwrap();
        assert!(all.beats_s.iter().any(|&t| t > 20.0), "{:?}", all.beats_s);
        let cut = learned(&act, &[], &[], Some(12.0), &BeatHints::default()).unwrap();
        let last = 12.0 + AFTER_MUSIC_END_S;
        assert!(cut.beats_s.iter().all(|&t| t <= last), "{:?}", cut.beats_s);
        assert!(cut.downbeats_s.iter().all(|&t| t <= last));
        // The beats before the end are the untrimmed decoding's.
        let before: Vec<f64> = all.beats_s.iter().copied().filter(|&t| t <= last).collect();
        assert_eq!(cut.beats_s, before);
        assert_eq!(cut.tempo_bpm, all.tempo_bpm);
        // Music ending before the first beat: nothing, and no tempo.
        let none = learned(&act, &[], &[], Some(-1.0), &BeatHints::default()).unwrap();
        assert!(none.beats_s.is_empty() && none.meter.is_none() && none.tempo_bpm == 0.0);
        // A NaN end is no end.
        let nan = learned(&act, &[], &[], Some(f64::NAN), &BeatHints::default()).unwrap();
        assert_eq!(nan.beats_s, all.beats_s);
    }

    #[test]
    fn the_classic_tracker_stops_at_the_end_too() {
        let sr = dsp_mel::DEFAULT_ANALYSIS_RATE_HZ;
        // Plucked A4s every 0.5 s for 12 s.
        let x: Vec<f32> = (0..12 * sr as usize)
            .map(|i| {
                let t = i as f32 / sr as f32;
                let since = t % 0.5;
                (-since * 12.0).exp() * (std::f32::consts::TAU * 440.0 * t).sin()
            })
            .collect();
        let notes: Vec<Note> = (0..24)
            .map(|k| Note::new(k as f64 * 0.5, k as f64 * 0.5 + 0.45, 69))
            .collect();
        let all = classic(&x, &notes, &[], None).unwrap();
        assert!(all.beats_s.iter().any(|&t| t > 8.0), "{:?}", all.beats_s);
        let cut = classic(&x, &notes, &[], Some(6.0)).unwrap();
        assert!(!cut.beats_s.is_empty());
        assert!(cut.beats_s.iter().all(|&t| t <= 6.0 + AFTER_MUSIC_END_S));
        assert!(cut
            .downbeats_s
            .iter()
            .all(|&t| t <= 6.0 + AFTER_MUSIC_END_S));
        let before: Vec<f64> = all.beats_s.iter().copied().filter(|&t| t <= 6.1).collect();
        assert_eq!(cut.beats_s, before);
        let none = classic(&x, &notes, &[], Some(-1.0)).unwrap();
        assert!(none.beats_s.is_empty() && none.meter.is_none() && none.tempo_bpm == 0.0);
    }

    #[test]
    fn the_music_ends_where_the_last_note_is_released() {
        let sr = 8_000u32;
        // A4 for 1 s, then its ring falling 60 dB/s for 1 s, then silence.
        let x: Vec<f32> = (0..3 * sr as usize)
            .map(|i| {
                let t = i as f32 / sr as f32;
                let db = if t < 1.0 { 0.0 } else { -60.0 * (t - 1.0) };
                10f32.powf(db / 20.0) * (std::f32::consts::TAU * 440.0 * t).sin()
            })
            .collect();
        let notes = [Note::new(0.2, 0.6, 64), Note::new(0.6, 1.9, 69)];
        let end = music_end_s(&notes, &x, sr).unwrap().unwrap();
        assert!((end - 1.1).abs() < 0.05, "{end}");
        assert_eq!(music_end_s(&[], &x, sr).unwrap(), None);
    }

    /// 30 s at 120 bpm, every beat alike (a downbeat probability of 0.3 on each): the bar
    /// length and the tempo level are the hints' to choose.
    fn ambiguous() -> Activations {
        let (mut beat, mut downbeat) = (vec![0.01f32; 900], vec![0.01f32; 900]);
        for k in (0..900).step_by(15) {
            beat[k] = 0.6;
            downbeat[k] = 0.3;
        }
        Activations { beat, downbeat }
    }

    #[test]
    fn hints_set_the_bar_and_the_tempo_level() {
        let act = ambiguous();
        let with = |ts: Option<&str>, tempo: Option<(f64, f64)>| {
            let hints = BeatHints {
                time_signature: ts.map(|t| t.parse().unwrap()),
                tempo_range_bpm: tempo,
            };
            learned(&act, &[], &[], None, &hints).unwrap()
        };
        for (ts, meter) in [
            ("3/4", Meter::THREE_FOUR),
            ("4/4", Meter::FOUR_FOUR),
            ("6/8", Meter::SIX_EIGHT),
        ] {
            let b = with(Some(ts), None);
            assert_eq!(b.meter, Some(meter), "{ts}");
            let per_bar = b.beats_s.len() as f64 / b.downbeats_s.len() as f64;
            assert!(
                (per_bar - f64::from(meter.beats_per_bar)).abs() < 0.3,
                "{ts}: {per_bar}"
            );
            assert!((b.tempo_bpm - 120.0).abs() < 3.0, "{ts}: {}", b.tempo_bpm);
        }
        // Every other beat when the user says the tempo is near 60.
        let slow = with(None, Some((52.0, 69.0)));
        assert!((slow.tempo_bpm - 60.0).abs() < 2.0, "{}", slow.tempo_bpm);
        // Hints the decoder cannot follow are refused.
        let bad = BeatHints {
            tempo_range_bpm: Some((90.0, 80.0)),
            ..BeatHints::default()
        };
        assert!(matches!(
            learned(&act, &[], &[], None, &bad),
            Err(Error::BeatHint(_))
        ));
        let long_bar = BeatHints {
            time_signature: Some(TimeSignature::new(13, 4)),
            ..BeatHints::default()
        };
        assert!(long_bar.check().is_err());
        assert!(BeatHints::default().check().is_ok() && BeatHints::default().is_empty());
    }
}
