//! Beat and downbeat accuracy on synthetic violin — corpus études rendered by the corpus's
//! bowed-string synthesizer — and behaviour on silence, short and damaged audio.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use beat_track::eval::{beat_prf, BEAT_TOLERANCE_S};
use beat_track::{
    estimate_tempo, BeatConfig, BeatError, BeatTracker, OnsetConfig, OnsetStrength, TempoConfig,
};
use corpus::etude::EtudeConfig;
use corpus::item::{clean_etude, CorpusItem};
use corpus::render::{BowedStringSynth, RenderSettings, Renderer};
use performance::Timeline;
use pitch_track::{segment_notes, NoteConfig, PitchConfig, PitchTracker};

const SR: u32 = 22_050;

/// Corpus item `seed`: an étude of about `seconds` at a tempo drawn from `tempo_bpm`, built-in
/// renderer, no augmentation (22 050 Hz).
fn item_at(seed: u64, seconds: f64, tempo_bpm: (f64, f64)) -> CorpusItem {
    clean_etude(seed, seconds, tempo_bpm).unwrap()
}

/// Corpus item `seed` at the corpus's tempi (50–170 bpm, any metre).
fn item(seed: u64, seconds: f64) -> CorpusItem {
    item_at(seed, seconds, EtudeConfig::default().tempo_bpm)
}

/// `timeline` with every time moved by `t ↦ t + depth · P/2π · sin(2π t / P)`: the local
/// tempo swings by ±`depth` once every `period_s`, on top of the corpus's own rubato.
fn warped(timeline: &Timeline, depth: f64, period_s: f64) -> Timeline {
    let w = |t: f64| {
        t + depth * period_s / std::f64::consts::TAU * (std::f64::consts::TAU * t / period_s).sin()
    };
    let mut out = timeline.clone();
    for n in &mut out.notes {
        n.note.onset_s = w(n.note.onset_s);
        n.note.offset_s = w(n.note.offset_s);
    }
    for t in out.beats_s.iter_mut().chain(out.downbeats_s.iter_mut()) {
        *t = w(*t);
    }
    out.duration_s = w(out.duration_s);
    out
}

#[test]
fn varied_pieces_meet_the_beat_and_downbeat_goals() {
    let tracker = BeatTracker::new(BeatConfig::default()).unwrap();
    let pitch = PitchTracker::new(PitchConfig::default()).unwrap();
    let (mut beat_sum, mut down_sum, mut down_plain_sum, mut n) = (0.0, 0.0, 0.0, 0.0);
    for seed in 1..=8 {
        let item = item(seed, 20.0);
        let samples = &item.audio;
        let truth = &item.timeline;
        let track = pitch.track(samples).unwrap();
        let notes = segment_notes(&track, samples, SR, &NoteConfig::default()).unwrap();
        // The strided tempogram mean gives librosa's every-window tempo.
        let env = OnsetStrength::new(OnsetConfig::default())
            .unwrap()
            .compute(samples)
            .unwrap();
        let tempo = |frame_stride| {
            let cfg = TempoConfig {
                frame_stride,
                ..TempoConfig::default()
            };
            estimate_tempo(&env.mean, SR, 512, &cfg)
        };
        assert_eq!(
            tempo(1),
            tempo(TempoConfig::default().frame_stride),
            "seed {seed}"
        );
        let with_notes = tracker.track(samples, Some(&notes)).unwrap();
        let plain = tracker.track(samples, None).unwrap();
        let beat = beat_prf(&truth.beats_s, &with_notes.beats_s, BEAT_TOLERANCE_S).f_measure;
        let down = beat_prf(
            &truth.downbeats_s,
            &with_notes.downbeats_s,
            BEAT_TOLERANCE_S,
        )
        .f_measure;
        let down_plain =
            beat_prf(&truth.downbeats_s, &plain.downbeats_s, BEAT_TOLERANCE_S).f_measure;
        println!(
            "seed {seed}: truth {:.0} bpm {} → {:.1} bpm {}/{}: beat F {beat:.3}, downbeat F {down:.3} (no notes {down_plain:.3})",
            truth.tempo_bpm, item.time_signature,
            with_notes.tempo_bpm, with_notes.meter.beats_per_bar, with_notes.meter.subdivisions
        );
        beat_sum += beat;
        down_sum += down;
        down_plain_sum += down_plain;
        n += 1.0;
    }
    println!(
        "mean beat F {:.3}, downbeat F {:.3} (no notes {:.3})",
        beat_sum / n,
        down_sum / n,
        down_plain_sum / n
    );
    assert!(beat_sum / n >= 0.85, "beat F {}", beat_sum / n);
    assert!(down_sum / n >= 0.70, "downbeat F {}", down_sum / n);
}

#[test]
fn silence_has_no_onsets_and_no_beats() {
    let tracker = BeatTracker::new(BeatConfig::default()).unwrap();
    let a = tracker.track(&vec![0.0; 22_050 * 3], None).unwrap();
    assert!(a.beats_s.is_empty() && a.downbeats_s.is_empty() && a.onsets_s.is_empty());
    assert_eq!(a.tempo_bpm, 0.0);
}

#[test]
fn short_audio_gives_few_beats_not_a_panic() {
    let tracker = BeatTracker::new(BeatConfig::default()).unwrap();
    let x: Vec<f32> = (0..2_205).map(|i| (i as f32 * 0.2).sin()).collect(); // 0.1 s
    let a = tracker.track(&x, Some(&[])).unwrap();
    assert!(a.beats_s.len() <= 1);
    assert!(a.downbeats_s.len() <= a.beats_s.len());
    let one = tracker.track(&[0.5], None).unwrap();
    assert!(one.beats_s.is_empty());
}

#[test]
fn bad_input_is_a_typed_error() {
    let tracker = BeatTracker::new(BeatConfig::default()).unwrap();
    assert!(matches!(
        tracker.track(&[], None),
        Err(BeatError::EmptyAudio)
    ));
    assert!(matches!(
        tracker.track(&[0.0, f32::NAN], None),
        Err(BeatError::NonFinite { index: 1 })
    ));
    assert!(BeatTracker::new(BeatConfig {
        tightness: 0.0,
        ..BeatConfig::default()
    })
    .is_err());
}

#[test]
fn rubato_is_followed() {
    // ±12 % tempo swing every 16 beats at 100 bpm: the DP follows beat by beat.
    let item = item_at(11, 29.0, (100.0, 100.0));
    let timeline = warped(&item.timeline, 0.12, 16.0 * 0.6);
    let samples = BowedStringSynth::default()
        .render(&timeline, &RenderSettings::default())
        .unwrap();
    let a = BeatTracker::new(BeatConfig::default())
        .unwrap()
        .track(&samples, None)
        .unwrap();
    let f = beat_prf(&timeline.beats_s, &a.beats_s, BEAT_TOLERANCE_S).f_measure;
    println!("{}: beat F {f:.3}", item.time_signature);
    assert!(f >= 0.85, "beat F {f}");
}

#[test]
fn the_chosen_level_is_the_best_scoring_candidate() {
    let samples = item(3, 20.0).audio;
    let tracker = BeatTracker::new(BeatConfig::default()).unwrap();
    let candidates = tracker.level_candidates(&samples, None).unwrap();
    assert!(candidates.len() >= 2, "{} candidates", candidates.len());
    assert!(candidates.len() <= BeatConfig::default().level.candidates);
    let best = candidates
        .iter()
        .reduce(|b, c| if c.score > b.score { c } else { b })
        .unwrap();
    for c in &candidates {
        assert!((c.score - c.features.score(&BeatConfig::default().level.weights)).abs() < 1e-12);
        assert!(c.beats_s.windows(2).all(|w| w[1] > w[0]));
    }
    let a = tracker.track(&samples, None).unwrap();
    // The metre step may keep every beat, or every second/third for a finer reading.
    let ratio = best.tempo_bpm / a.tempo_bpm;
    assert!(
        [1.0, 2.0, 3.0].iter().any(|r| (ratio - r).abs() < 1e-9),
        "candidate {} bpm, result {} bpm",
        best.tempo_bpm,
        a.tempo_bpm
    );
    // Without a level choice the tracker is librosa's beat_track (frame times, no latency).
    let librosa = BeatTracker::new(BeatConfig {
        level: beat_track::LevelConfig {
            candidates: 0,
            ..Default::default()
        },
        ..BeatConfig::default()
    })
    .unwrap();
    assert!(librosa.level_candidates(&samples, None).unwrap().is_empty());
    assert!(!librosa.track(&samples, None).unwrap().beats_s.is_empty());
}

#[test]
fn beats_are_reported_latency_earlier() {
    let samples = item(5, 15.0).audio;
    let at = |latency_s| {
        BeatTracker::new(BeatConfig {
            latency_s,
            ..BeatConfig::default()
        })
        .unwrap()
        .level_candidates(&samples, None)
        .unwrap()
    };
    let (none, some) = (at(0.0), at(0.04));
    // Same candidates, every beat (but one clamped at 0) 40 ms earlier.
    assert_eq!(none.len(), some.len());
    for (a, b) in none.iter().zip(&some) {
        assert_eq!(a.tempo_bpm, b.tempo_bpm);
        for (x, y) in a.beats_s.iter().zip(&b.beats_s) {
            assert!((y - (x - 0.04).max(0.0)).abs() < 1e-9);
        }
    }
    for bad in [-0.01, f64::NAN] {
        assert!(BeatTracker::new(BeatConfig {
            latency_s: bad,
            ..BeatConfig::default()
        })
        .is_err());
    }
}

#[test]
fn the_same_input_gives_the_same_beats() {
    let samples = item(7, 15.0).audio;
    let tracker = BeatTracker::new(BeatConfig::default()).unwrap();
    let a = tracker.track(&samples, None).unwrap();
    let b = tracker.track(&samples, None).unwrap();
    assert_eq!(a, b);
}

#[test]
fn bow_changes_on_the_beats_cover_the_labelled_level_only() {
    let item = item(4, 20.0);
    let (samples, truth) = (&item.audio, &item.timeline);
    let tracker = BeatTracker::new(BeatConfig::default()).unwrap();
    let evidence = beat_track::BarEvidence {
        notes: None,
        bow_changes_s: Some(&truth.beats_s),
    };
    let with_bows = tracker.level_candidates_with(samples, evidence).unwrap();
    let at = |ratio: f64| {
        with_bows
            .iter()
            .find(|c| (c.tempo_bpm / truth.tempo_bpm / ratio - 1.0).abs() < 0.05)
    };
    let labelled = at(1.0).expect("a candidate at the labelled tempo");
    println!(
        "bow coverage at the labelled tempo {:.3}, at double {:?}",
        labelled.features.bow_coverage,
        at(2.0).map(|c| c.features.bow_coverage)
    );
    assert!(
        labelled.features.bow_coverage >= 0.9,
        "{:?}",
        labelled.features
    );
    if let Some(double) = at(2.0) {
        assert!(double.features.bow_coverage <= 0.6, "{:?}", double.features);
    }
    // Without bow changes the detected onsets stand in for them.
    for c in tracker.level_candidates(samples, None).unwrap() {
        assert_eq!(c.features.bow_coverage, c.features.onset_coverage);
    }
}

#[test]
fn no_beats_in_the_silence_around_the_music() {
    let item = item_at(6, 14.0, (100.0, 100.0));
    let pad = 8 * SR as usize;
    let mut samples = vec![0.0f32; pad];
    samples.extend_from_slice(&item.audio);
    samples.extend(std::iter::repeat_n(0.0f32, pad));
    let offset_s = pad as f64 / f64::from(SR);
    let music_end_s = offset_s + item.audio.len() as f64 / f64::from(SR);
    let a = BeatTracker::new(BeatConfig::default())
        .unwrap()
        .track(&samples, None)
        .unwrap();
    assert!(a.beats_s.len() >= 8, "{:?}", a.beats_s);
    assert!(
        a.beats_s
            .iter()
            .all(|&b| b >= offset_s - 0.1 && b <= music_end_s),
        "music {offset_s:.2}–{music_end_s:.2} s, beats {:?}",
        a.beats_s
    );
    let shifted: Vec<f64> = item.timeline.beats_s.iter().map(|b| b + offset_s).collect();
    let f = beat_prf(&shifted, &a.beats_s, BEAT_TOLERANCE_S).f_measure;
    println!("{}: beat F {f:.3}", item.time_signature);
    assert!(f >= 0.8, "beat F {f}");
}

#[test]
fn a_lone_blip_gives_a_tempo_only_with_beats() {
    let sr = 22_050usize;
    let mut samples = vec![0.0f32; 20 * sr];
    for (i, s) in samples[19 * sr..19 * sr + 2000].iter_mut().enumerate() {
        *s = 0.5 * (2.0 * std::f32::consts::PI * 660.0 * i as f32 / sr as f32).sin();
    }
    let a = BeatTracker::new(BeatConfig::default())
        .unwrap()
        .track(&samples, None)
        .unwrap();
    assert_eq!(a.beats_s.is_empty(), a.tempo_bpm == 0.0, "{a:?}");
    assert!(a.beats_s.iter().all(|&b| b >= 18.9), "{:?}", a.beats_s);
}
