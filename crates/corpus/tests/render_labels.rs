//! The built-in renderer's audio agrees with the labels: bow changes leave an acoustic trace
//! (amplitude dip, new attack), slurred changes do not (but a repeated pitch does), onsets are
//! on time, rests are silent.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use corpus::etude::{generate, EtudeConfig};
use corpus::render::{BowedStringSynth, RenderSettings, Renderer};
use corpus::timing::play;
use fingering::OptimalPlanner;
use performance::Timeline;

const SR: u32 = 22_050;

fn render(seed: u64) -> (Timeline, Vec<f32>) {
    let mut t = play(&generate(seed, &EtudeConfig::default()), seed);
    t.assign_fingering(&OptimalPlanner::default());
    let settings = RenderSettings {
        sample_rate_hz: SR,
        tuning_cents: 0.0,
        seed,
    };
    let audio = BowedStringSynth::default().render(&t, &settings).unwrap();
    (t, audio)
}

/// RMS over a window [a, b) seconds.
fn rms(audio: &[f32], a: f64, b: f64) -> f64 {
    let i0 = ((a * f64::from(SR)) as usize).min(audio.len());
    let i1 = ((b * f64::from(SR)) as usize).min(audio.len()).max(i0 + 1);
    let s: f64 = audio[i0..i1.min(audio.len())]
        .iter()
        .map(|x| f64::from(*x).powi(2))
        .sum();
    (s / (i1 - i0) as f64).sqrt()
}

/// Smallest 5 ms RMS around a note change relative to the level just before it.
fn dip_ratio(audio: &[f32], onset: f64) -> f64 {
    let before = rms(audio, onset - 0.09, onset - 0.05);
    let lowest = (0..10)
        .map(|k| {
            let a = onset - 0.035 + 0.005 * f64::from(k);
            rms(audio, a, a + 0.005)
        })
        .fold(f64::MAX, f64::min);
    lowest / before.max(1e-12)
}

#[test]
fn bow_changes_dip_and_slurs_do_not() {
    let (mut change_ratios, mut slur_ratios, mut portato_ratios) =
        (Vec::new(), Vec::new(), Vec::new());
    for seed in 0..6 {
        let (t, audio) = render(seed);
        for w in t.notes.windows(2) {
            let (prev, note) = (&w[0], &w[1]);
            // Only joined changes between notes long enough to measure, same dynamic region.
            let joined = note.note.onset_s - prev.note.offset_s < 0.05;
            if !joined || note.note.onset_s - prev.note.onset_s < 0.15 {
                continue;
            }
            let r = dip_ratio(&audio, note.note.onset_s);
            if note.bow_change {
                change_ratios.push(r);
            } else if note.note.midi == prev.note.midi {
                portato_ratios.push(r);
            } else {
                slur_ratios.push(r);
            }
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (n_change, n_slur) = (change_ratios.len(), slur_ratios.len());
    assert!(
        n_change > 20 && n_slur > 20,
        "{n_change} changes, {n_slur} slurs"
    );
    let change = median(&mut change_ratios);
    let slur = median(&mut slur_ratios);
    println!("median dip ratio: bow changes {change:.2} ({n_change}), slurred changes {slur:.2} ({n_slur})");
    assert!(change < 0.5, "bow changes should dip: {change}");
    // A repeated pitch under one bow (portato) dips too, or it would be a tie.
    assert!(
        portato_ratios.len() > 5,
        "{} portato notes",
        portato_ratios.len()
    );
    let portato = median(&mut portato_ratios);
    println!(
        "median dip ratio: portato {portato:.2} ({})",
        portato_ratios.len()
    );
    assert!(portato < 0.5, "portato notes should dip: {portato}");
    assert!(slur > 0.75, "slurred changes should not dip: {slur}");
    // Nearly every slurred change stays above every typical bow change.
    let slur_dips = slur_ratios.iter().filter(|r| **r < 0.5).count();
    assert!(
        slur_dips * 20 < n_slur,
        "{slur_dips} of {n_slur} slurred changes dip"
    );
}

#[test]
fn onsets_after_rests_are_on_time_and_rests_are_silent() {
    let mut errors_ms = Vec::new();
    for seed in 0..12 {
        let (t, audio) = render(seed);
        let peak = audio.iter().fold(0.0f32, |m, x| m.max(x.abs())) as f64;
        for w in t.notes.windows(2) {
            let (prev, note) = (&w[0], &w[1]);
            let gap = note.note.onset_s - prev.note.offset_s;
            if gap < 0.25 {
                continue;
            }
            // The rest (after the release tail) is silent.
            let quiet = rms(&audio, prev.note.offset_s + 0.2, note.note.onset_s - 0.01);
            assert!(
                quiet < peak * 1e-3,
                "seed {seed}: rest at {:.2}s not silent",
                prev.note.offset_s
            );
            // Energy onset: first 1 ms block above 10 % of the note's level.
            let level = rms(&audio, note.note.onset_s + 0.06, note.note.onset_s + 0.1);
            let start = note.note.onset_s - 0.03;
            let first = (0..80)
                .map(|k| start + 0.001 * f64::from(k))
                .find(|a| rms(&audio, *a, a + 0.001) > 0.1 * level)
                .unwrap();
            errors_ms.push((first - note.note.onset_s).abs() * 1e3);
        }
    }
    assert!(errors_ms.len() > 10);
    let worst = errors_ms.iter().cloned().fold(0.0, f64::max);
    println!(
        "energy onset vs label after rests: worst {worst:.1} ms over {}",
        errors_ms.len()
    );
    assert!(worst <= 10.0, "{worst} ms");
}

#[test]
fn rendering_is_deterministic_and_finite() {
    let (_, a) = render(11);
    let (_, b) = render(11);
    assert_eq!(a, b);
    assert!(a.iter().all(|x| x.is_finite() && x.abs() < 1.0));
}
