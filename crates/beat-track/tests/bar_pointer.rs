//! The bar-pointer decoder on synthetic activations: steady tempo, ritardando, 3/4 against
//! 4/4, compound and one-beat bars, and the bad inputs (silence, a single spike, 2 s,
//! noise, a long silent gap, malformed activations).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use beat_track::bar_pointer::{decode, BarPointerConfig};
use beat_track::eval::beat_prf;

const FPS: f64 = 30.0;

/// Activations with a peak at every beat (`bar` beats per bar, the first a downbeat) over
/// `frames` frames.
fn activations(beats_s: &[f64], bar: usize, frames: usize) -> (Vec<f32>, Vec<f32>) {
    let mut beat = vec![0.02f32; frames];
    let mut down = vec![0.01f32; frames];
    for (i, &t) in beats_s.iter().enumerate() {
        let f = (t * FPS).round() as usize;
        if f >= frames {
            continue;
        }
        let target = if i % bar == 0 { &mut down } else { &mut beat };
        target[f] = 0.85;
        if f > 0 {
            target[f - 1] = target[f - 1].max(0.3);
        }
        if f + 1 < frames {
            target[f + 1] = target[f + 1].max(0.3);
        }
    }
    (beat, down)
}

fn steady(bpm: f64, from_s: f64, to_s: f64) -> Vec<f64> {
    let step = 60.0 / bpm;
    (0..)
        .map(|k| from_s + k as f64 * step)
        .take_while(|&t| t < to_s)
        .collect()
}

fn downbeats(beats: &[f64], bar: usize) -> Vec<f64> {
    beats.iter().step_by(bar).copied().collect()
}

#[test]
fn steady_tempo_in_four_four() {
    let beats = steady(100.0, 0.5, 60.0);
    let (b, d) = activations(&beats, 4, 1800);
    let out = decode(&b, &d, &BarPointerConfig::default()).unwrap();
    assert_eq!(out.beats_per_bar, 4);
    assert!(beat_prf(&beats, &out.beats_s, 0.07).f_measure > 0.97);
    let f = beat_prf(&downbeats(&beats, 4), &out.downbeats_s, 0.07).f_measure;
    assert!(f > 0.95, "{f}");
    assert!((out.tempo_bpm - 100.0).abs() < 2.0, "{}", out.tempo_bpm);
    assert_eq!(out.tempo_bpm_per_beat.len(), out.beats_s.len());
    assert!(out.confidence > 0.7);
}

#[test]
fn ritardando_is_followed() {
    // Intervals grow from 0.45 s to 0.9 s over 40 beats.
    let mut beats = vec![1.0];
    for k in 0..40 {
        let last = beats[beats.len() - 1];
        beats.push(last + 0.45 + 0.45 * f64::from(k) / 39.0);
    }
    let frames = ((beats[beats.len() - 1] + 1.0) * FPS) as usize;
    let (b, d) = activations(&beats, 3, frames);
    let out = decode(&b, &d, &BarPointerConfig::default()).unwrap();
    let f = beat_prf(&beats, &out.beats_s, 0.07).f_measure;
    assert!(f > 0.9, "{f}");
    let first = out.tempo_bpm_per_beat[2];
    let last = out.tempo_bpm_per_beat[out.tempo_bpm_per_beat.len() - 2];
    assert!(first > 110.0 && last < 75.0, "{first} → {last}");
}

#[test]
fn three_four_and_four_four_are_told_apart() {
    for bar in [3, 4, 2] {
        let beats = steady(90.0, 0.3, 45.0);
        let (b, d) = activations(&beats, bar, 1350);
        let out = decode(&b, &d, &BarPointerConfig::default()).unwrap();
        assert_eq!(out.beats_per_bar, bar);
        let f = beat_prf(&downbeats(&beats, bar), &out.downbeats_s, 0.07).f_measure;
        assert!(f > 0.95, "{bar}: {f}");
    }
}

#[test]
fn compound_and_one_beat_bars() {
    // 6/8 at 60 dotted-quarter beats per minute: two beats per bar, slow beats.
    let beats = steady(60.0, 0.2, 60.0);
    let (b, d) = activations(&beats, 2, 1800);
    let out = decode(&b, &d, &BarPointerConfig::default()).unwrap();
    assert_eq!(out.beats_per_bar, 2);
    assert!((out.tempo_bpm - 60.0).abs() < 2.0, "{}", out.tempo_bpm);
    // 3/8: every beat is a downbeat.
    let beats = steady(70.0, 0.2, 40.0);
    let (b, d) = activations(&beats, 1, 1200);
    let out = decode(&b, &d, &BarPointerConfig::default()).unwrap();
    assert_eq!(out.beats_per_bar, 1);
    assert_eq!(out.downbeats_s.len(), out.beats_s.len());
}

#[test]
fn silence_noise_and_a_single_spike_give_no_beats() {
    let cfg = BarPointerConfig::default();
    let out = decode(&vec![0.0; 1800], &vec![0.0; 1800], &cfg).unwrap();
    assert!(out.beats_s.is_empty() && out.confidence == 0.0 && out.tempo_bpm == 0.0);
    let mut spike = vec![0.0f32; 1800];
    spike[900] = 0.95;
    let out = decode(&spike, &vec![0.0; 1800], &cfg).unwrap();
    assert!(out.beats_s.len() <= 3, "{:?}", out.beats_s);
    assert!(out.confidence < 0.1);
    // Noise: a seeded sequence of small activations.
    let mut x = 12345u64;
    let mut noise = || {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((x >> 40) as f32 / (1u64 << 24) as f32) * 0.08
    };
    let (b, d): (Vec<f32>, Vec<f32>) = (0..1800).map(|_| (noise(), noise() * 0.5)).unzip();
    let out = decode(&b, &d, &cfg).unwrap();
    assert!(out.beats_s.is_empty(), "{}", out.beats_s.len());
    assert!(out.confidence < 0.1);
}

#[test]
fn short_inputs_and_a_long_gap() {
    let cfg = BarPointerConfig::default();
    // 2 s.
    let beats = steady(120.0, 0.1, 2.0);
    let (b, d) = activations(&beats, 4, 60);
    let out = decode(&b, &d, &cfg).unwrap();
    assert!(out.beats_s.len() <= 5);
    for n in [0, 1, 2] {
        decode(&vec![0.5; n], &vec![0.1; n], &cfg).unwrap();
    }
    // Beats for 20 s, 30 s of silence, 20 s of beats.
    let mut beats = steady(100.0, 0.5, 20.0);
    beats.extend(steady(100.0, 50.0, 70.0));
    let (b, d) = activations(&beats, 4, 2100);
    let mut d = d;
    let mut b = b;
    for f in 20 * 30..50 * 30 {
        b[f] = 0.0;
        d[f] = 0.0;
    }
    let out = decode(&b, &d, &cfg).unwrap();
    assert!(
        !out.beats_s.iter().any(|&t| (22.0..48.0).contains(&t)),
        "{:?}",
        out.beats_s
    );
    let f = beat_prf(&beats, &out.beats_s, 0.07);
    assert!(f.f_measure > 0.9, "{f:?} {:?}", out.beats_s);
}

#[test]
fn malformed_activations_are_refused() {
    let cfg = BarPointerConfig::default();
    assert!(decode(&[0.1, 0.2], &[0.1], &cfg).is_err());
    assert!(decode(&[0.1, f32::NAN], &[0.1, 0.1], &cfg).is_err());
    assert!(decode(&[0.1, 1.5], &[0.1, 0.1], &cfg).is_err());
    let bad = BarPointerConfig {
        beats_per_bar: vec![],
        ..Default::default()
    };
    assert!(decode(&[0.1; 10], &[0.1; 10], &bad).is_err());
}

#[test]
fn the_bar_length_prior_is_checked_and_can_tip_the_metre() {
    // 20 s at 30 fps, a beat every 15 frames, every third one a downbeat.
    let (mut beat, mut down) = (vec![0.02f32; 600], vec![0.01f32; 600]);
    for k in (0..600).step_by(15) {
        if (k / 15) % 3 == 0 {
            down[k] = 0.9
        } else {
            beat[k] = 0.9
        }
    }
    let neutral = BarPointerConfig {
        bar_length_prior_per_frame: Vec::new(),
        ..Default::default()
    };
    assert_eq!(decode(&beat, &down, &neutral).unwrap().beats_per_bar, 3);
    assert_eq!(
        decode(&beat, &down, &BarPointerConfig::default())
            .unwrap()
            .beats_per_bar,
        3,
        "the shipped prior leaves a clear metre alone"
    );
    let pushed = BarPointerConfig {
        bar_length_prior_per_frame: vec![0.0, 0.0, 0.0, 1.0],
        ..Default::default()
    };
    assert_eq!(decode(&beat, &down, &pushed).unwrap().beats_per_bar, 4);
    let wrong_length = BarPointerConfig {
        bar_length_prior_per_frame: vec![0.0; 3],
        ..Default::default()
    };
    assert!(decode(&beat, &down, &wrong_length).is_err());
    let not_finite = BarPointerConfig {
        bar_length_prior_per_frame: vec![0.0, f64::NAN, 0.0, 0.0],
        ..Default::default()
    };
    assert!(decode(&beat, &down, &not_finite).is_err());
}

#[test]
fn a_slow_beat_with_a_pulse_between_is_not_doubled() {
    // Without the 0.05 s observing region and the finer decoding grid, these were
    // decoded at twice the tempo (90 and 109 bpm).
    for bpm in [45.0f64, 55.0] {
        let mut beats = Vec::new();
        let mut t: f64 = 0.5;
        while t < 60.0 {
            beats.push(t);
            t += 60.0 / bpm * (1.0 + 0.03 * (t / 7.0).sin());
        }
        let (mut b, mut d) = activations(&beats, 2, 1800);
        for v in b.iter_mut().chain(d.iter_mut()) {
            *v = v.min(0.5);
        }
        // An eighth-note pulse between the beats, weaker than the beats.
        for w in beats.windows(2) {
            let f = ((w[0] + w[1]) * FPS / 2.0).round() as usize;
            b[f] = b[f].max(0.2);
        }
        let out = decode(&b, &d, &BarPointerConfig::default()).unwrap();
        assert!(
            (out.tempo_bpm / bpm - 1.0).abs() < 0.08,
            "{bpm}: {}",
            out.tempo_bpm
        );
        assert!(beat_prf(&beats, &out.beats_s, 0.07).f_measure > 0.95);
    }
}

#[test]
fn the_decoding_grid_is_checked() {
    for bad in [
        BarPointerConfig {
            upsample: 0,
            ..Default::default()
        },
        BarPointerConfig {
            observation_floor: 1.0,
            ..Default::default()
        },
        BarPointerConfig {
            max_beat_region_s: f64::NAN,
            ..Default::default()
        },
        BarPointerConfig {
            selection_upsample: 9,
            ..Default::default()
        },
    ] {
        assert!(decode(&[0.1; 10], &[0.1; 10], &bad).is_err(), "{bad:?}");
    }
    let cfg = BarPointerConfig::default();
    let intervals = cfg.intervals();
    assert!(intervals.len() <= cfg.max_tempi);
    assert!(intervals.windows(2).all(|w| w[0] < w[1]));
    // Slowest and fastest tempo at the decoding rate (30 fps × 2).
    assert_eq!(intervals[0], (60.0 * 60.0 / cfg.max_bpm).floor() as usize);
    assert_eq!(
        *intervals.last().unwrap(),
        (60.0 * 60.0 / cfg.min_bpm).ceil() as usize
    );
}

#[test]
fn downbeat_evidence_moves_the_phase_not_the_bar_length() {
    use beat_track::bar_pointer::decode_with_downbeat_evidence;
    // 40 s at 100 bpm in 3/4 whose downbeat activation sits on the bar's first beat.
    let beats = steady(100.0, 0.5, 40.0);
    let (mut b, mut d) = activations(&beats, 3, 1200);
    // A weak downbeat activation on the other beats and a weak beat activation on the
    // downbeats, so the phase is a close call…
    for (i, &t) in beats.iter().enumerate() {
        let f = (t * FPS).round() as usize;
        if i % 3 == 0 {
            b[f] = 0.3;
        } else {
            d[f] = 0.3;
        }
    }
    let cfg = BarPointerConfig::default();
    let plain = decode(&b, &d, &cfg).unwrap();
    assert_eq!(plain.beats_per_bar, 3);
    // …and new bows start on the second beat of every bar.
    let mut bows = vec![0.0f32; 1200];
    for (i, &t) in beats.iter().enumerate() {
        if i % 3 == 1 {
            bows[(t * FPS).round() as usize] = 4.0;
        }
    }
    let out = decode_with_downbeat_evidence(&b, &d, &bows, &cfg).unwrap();
    assert_eq!(out.beats_per_bar, 3);
    assert_eq!(out.log_probability, plain.log_probability);
    let second: Vec<f64> = beats.iter().skip(1).step_by(3).copied().collect();
    assert!(beat_prf(&second, &out.downbeats_s, 0.07).f_measure > 0.9);
    assert!(beat_prf(&downbeats(&beats, 3), &plain.downbeats_s, 0.07).f_measure > 0.9);
    // Evidence of the wrong length or not finite is refused.
    assert!(decode_with_downbeat_evidence(&b, &d, &bows[1..], &cfg).is_err());
    bows[5] = f32::NAN;
    assert!(decode_with_downbeat_evidence(&b, &d, &bows, &cfg).is_err());
    // Also when the activation is silent and nothing would be decoded.
    let silent = vec![0.0f32; 1200];
    assert!(decode_with_downbeat_evidence(&silent, &silent, &bows, &cfg).is_err());
}

#[test]
fn the_bar_length_may_be_chosen_at_another_rate() {
    // 60 s of 3/4 at 100 bpm with a ritardando to 80 in the last 20 s.
    let mut beats = steady(100.0, 0.5, 40.0);
    let mut t = *beats.last().unwrap();
    while t < 59.0 {
        t += 60.0 / (100.0 - (t - 40.0));
        beats.push(t);
    }
    let (b, d) = activations(&beats, 3, 1800);
    let shipped = BarPointerConfig::default();
    let same_rate = BarPointerConfig {
        selection_upsample: shipped.upsample,
        ..Default::default()
    };
    let coarse = BarPointerConfig {
        selection_upsample: 1,
        ..Default::default()
    };
    let reference = decode(&b, &d, &shipped).unwrap();
    assert_eq!(reference.beats_per_bar, 3);
    // 0 means the decoding rate: the same decoding, bit for bit.
    assert_eq!(decode(&b, &d, &same_rate).unwrap(), reference);
    // Chosen at 30 fps: the same bar length, and the beats of the 60 fps decoding;
    // only the log-probabilities are those of the coarser selection.
    let out = decode(&b, &d, &coarse).unwrap();
    assert_eq!(out.beats_per_bar, 3);
    assert_eq!(out.beats_s, reference.beats_s);
    assert_eq!(out.downbeats_s, reference.downbeats_s);
    assert_ne!(out.log_probability, reference.log_probability);
}

#[test]
fn a_lone_onset_gives_no_tempo_and_a_few_beats_a_low_confidence() {
    let cfg = BarPointerConfig::default();
    // One note in 3.5 s, and two (a second apart) in 4 s: no pulse to tell a tempo by.
    for (peaks, frames) in [(vec![1.0], 105), (vec![1.0, 2.0], 120)] {
        let (b, d) = activations(&peaks, 4, frames);
        let out = decode(&b, &d, &cfg).unwrap();
        assert!(
            out.beats_s.is_empty() && out.tempo_bpm == 0.0 && out.confidence == 0.0,
            "{peaks:?}: {out:?}"
        );
    }
    // Beats returned are at least `min_beats`, and their confidence grows with their
    // number up to `full_confidence_beats`.
    let confidence = |to_s: f64| {
        let beats = steady(120.0, 0.5, to_s);
        let (b, d) = activations(&beats, 4, (to_s * FPS) as usize + 15);
        let out = decode(&b, &d, &cfg).unwrap();
        assert!(out.beats_s.len() >= cfg.min_beats, "{out:?}");
        assert!((out.tempo_bpm - 120.0).abs() < 5.0, "{out:?}");
        (out.beats_s.len(), out.confidence)
    };
    let (few, low) = confidence(2.5);
    let (many, high) = confidence(20.0);
    assert!(few < cfg.full_confidence_beats && many >= cfg.full_confidence_beats);
    assert!(low < 0.75 * high, "{few} beats {low}, {many} beats {high}");
}
