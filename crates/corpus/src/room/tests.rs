//! Tests of the recording chain.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use super::*;
use crate::render::Biquad;

fn room(rt60_s: f64, seed: u64) -> Recording {
    Recording {
        channels: 2,
        room_size_m: 14.0,
        rt60_s,
        mic_distance_m: 3.0,
        mic_angle_rad: 0.2,
        mic_height_m: 1.5,
        interchannel_delay_ms: 0.4,
        interchannel_level_db: -1.5,
        peak_dbfs: -6.0,
        seed,
        ..Recording::dry(44_100)
    }
}

fn tone(n: usize, sr: f64) -> Vec<f32> {
    (0..n)
        .map(|i| {
            let t = i as f64 / sr;
            (0.3 * (std::f64::consts::TAU * 440.0 * t).sin()
                + 0.1 * (std::f64::consts::TAU * 1320.0 * t).sin()) as f32
        })
        .collect()
}

#[test]
fn rt60_of_the_response_matches_the_draw() {
    let sr = 44_100.0;
    for rt in [0.5, 1.5] {
        for seed in [1u64, 2] {
            let ir = room(rt, seed).impulse_response(0, 44_100);
            // Mid band (the drawn RT60 is the mid-band value): a 1 kHz octave band-pass.
            let mut bp = Biquad::bandpass(sr, 1_000.0, 1.41);
            let band: Vec<f64> = ir.iter().map(|x| bp.process(*x)).collect();
            let measured = rt60_schroeder(&band, sr).unwrap();
            let broadband = rt60_schroeder(&ir, sr).unwrap();
            println!(
                "RT60 {rt} s, seed {seed}: mid band {measured:.3} s, broadband {broadband:.3} s"
            );
            assert!(
                (measured / rt - 1.0).abs() < 0.25,
                "drawn {rt} s, measured {measured} s"
            );
        }
    }
}

#[test]
fn a_distant_microphone_hears_more_room() {
    let near = Recording {
        mic_distance_m: 0.5,
        ..room(1.0, 3)
    };
    let far = Recording {
        mic_distance_m: 6.0,
        ..room(1.0, 3)
    };
    assert!(near.drr_db() > far.drr_db() + 15.0);
    let tail_share = |r: &Recording| {
        let ir = r.impulse_response(0, 44_100);
        let late: f64 = ir[2_000..].iter().map(|x| x * x).sum();
        late / ir.iter().map(|x| x * x).sum::<f64>()
    };
    assert!(tail_share(&far) > 5.0 * tail_share(&near));
}

#[test]
fn convolving_a_unit_impulse_returns_the_response() {
    let rec = room(0.7, 4);
    let ir = rec.impulse_response(1, 44_100);
    let mut impulse = vec![0.0; ir.len() + 500];
    impulse[0] = 1.0;
    let out = ir::convolve(&impulse, &ir).unwrap();
    let err = ir
        .iter()
        .zip(&out)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(err < 1e-9, "max error {err}");
    assert!(out[ir.len()..].iter().all(|x| x.abs() < 1e-9));
    // Against direct convolution on a short random signal crossing several blocks.
    let mut rng = Rng::new(5);
    let x: Vec<f64> = (0..3 * ir.len()).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let short = &ir[..300];
    let fast = ir::convolve(&x, short).unwrap();
    for i in (0..x.len()).step_by(997) {
        let slow: f64 = (0..=i.min(299)).map(|k| short[k] * x[i - k]).sum();
        assert!((slow - fast[i]).abs() < 1e-9, "{i}: {slow} vs {}", fast[i]);
    }
}

#[test]
fn output_peak_is_the_drawn_peak_and_channels_differ() {
    let sr = 44_100;
    let input = tone(30_000, 44_100.0);
    for seed in 0..20u64 {
        let rec = Recording::draw(&mut Rng::new(seed));
        let out = rec.apply(&input, sr).unwrap();
        assert_eq!(out.len(), usize::from(rec.channels));
        assert!(out.iter().all(|c| c.len() == input.len()));
        let peak = out.iter().flatten().fold(0.0f32, |m, x| m.max(x.abs()));
        let db = 20.0 * f64::from(peak).log10();
        assert!(
            (db - rec.peak_dbfs).abs() < 0.1,
            "{db} vs {}",
            rec.peak_dbfs
        );
        assert!(peak < 1.0);
        if rec.channels == 2 && rec.rt60_s > 0.0 {
            assert_ne!(out[0], out[1]);
        }
    }
}

#[test]
fn each_noise_lands_at_its_snr() {
    let sr = 44_100;
    let input = tone(44_100, 44_100.0);
    let signal_power = |x: &[f32]| x.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>();
    for kind in [
        NoiseKind::Pink,
        NoiseKind::Hum { mains_hz: 50 },
        NoiseKind::Hiss { cutoff_hz: 3_000.0 },
    ] {
        for snr_db in [15.0, 40.0] {
            let clean = Recording {
                peak_dbfs: -10.0,
                ..Recording::dry(sr)
            };
            let noisy = Recording {
                noise: vec![NoiseSpec {
                    kind: kind.clone(),
                    snr_db,
                }],
                seed: 8,
                ..clean.clone()
            };
            // Output = g · (input + noise); g by projection on the (uncorrelated) input.
            let b = &noisy.apply(&input, sr).unwrap()[0];
            let dot: f64 = b
                .iter()
                .zip(&input)
                .map(|(y, x)| f64::from(*y) * f64::from(*x))
                .sum();
            let g = dot / signal_power(&input);
            let noise: Vec<f32> = b
                .iter()
                .zip(&input)
                .map(|(y, x)| (f64::from(*y) / g - f64::from(*x)) as f32)
                .collect();
            let measured = 10.0 * (signal_power(&input) / signal_power(&noise)).log10();
            println!("{kind:?} at {snr_db} dB: measured {measured:.2} dB");
            assert!(
                (measured - snr_db).abs() < 2.0,
                "{kind:?}: {measured} vs {snr_db}"
            );
        }
    }
}

#[test]
fn the_same_seed_gives_identical_output() {
    let input = tone(20_000, 48_000.0);
    let rec = Recording::draw(&mut Rng::new(42));
    let a = rec.apply(&input, 48_000).unwrap();
    let b = Recording::draw(&mut Rng::new(42))
        .apply(&input, 48_000)
        .unwrap();
    assert_eq!(a, b);
    let json = serde_json::to_string(&rec).unwrap();
    let back: Recording = serde_json::from_str(&json).unwrap();
    assert_eq!(back, rec);
}

#[test]
fn silence_stays_finite_and_empty_stays_empty() {
    for seed in 0..10u64 {
        let mut rec = Recording::draw(&mut Rng::new(seed));
        rec.noise.push(NoiseSpec {
            kind: NoiseKind::Pink,
            snr_db: 20.0,
        });
        let out = rec.apply(&vec![0.0; 5_000], rec.sample_rate_hz).unwrap();
        assert!(out
            .iter()
            .flatten()
            .all(|x| x.is_finite() && x.abs() < 1e-3));
        assert!(out.iter().flatten().any(|x| *x != 0.0), "noise only");
        let empty = rec.apply(&[], rec.sample_rate_hz).unwrap();
        assert_eq!(empty.len(), usize::from(rec.channels));
        assert!(empty.iter().all(Vec::is_empty));
    }
    let rec = Recording::dry(44_100);
    assert!(rec.apply(&[f32::NAN, 1.0], 44_100).unwrap()[0]
        .iter()
        .all(|x| x.is_finite()));
    assert!(rec.apply(&[0.5], 0).is_err());
}

#[test]
fn draws_cover_the_ranges() {
    let mut rng = Rng::new(1);
    let draws: Vec<Recording> = (0..400).map(|_| Recording::draw(&mut rng)).collect();
    let rates: Vec<u32> = draws.iter().map(|r| r.sample_rate_hz).collect();
    let common = rates
        .iter()
        .filter(|r| **r == 44_100 || **r == 48_000)
        .count();
    assert!(common > 250, "{common}");
    for r in &draws {
        assert!((0.0..=2.0).contains(&r.rt60_s));
        assert!((0.3..=8.0001).contains(&r.mic_distance_m));
        assert!((-40.0..=-1.0).contains(&r.peak_dbfs));
        assert!(r.noise.iter().all(|n| (15.0..=60.0).contains(&n.snr_db)));
        if let Some(l) = r.lossy {
            match l.kind {
                LossyKind::Mp3 => {
                    assert!((64..=192).contains(&l.quality) && r.sample_rate_hz <= 48_000)
                }
                LossyKind::Vorbis => assert!(l.quality <= 6),
            }
        }
    }
    let lossy = draws.iter().filter(|r| r.lossy.is_some()).count();
    assert!((80..160).contains(&lossy), "{lossy}");
    assert!(draws.iter().any(|r| r.rt60_s == 0.0));
    assert!(draws.iter().any(|r| r.channels == 2) && draws.iter().any(|r| r.channels == 1));
}
