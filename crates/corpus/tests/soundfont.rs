//! The SoundFont renderer with a tiny SF2 made by our own code (no system package needed).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use corpus::render::{tiny_violin_sf2, RenderError, RenderSettings, Renderer, SoundFontRenderer};
use performance::{Note, TimedNote, Timeline};

const SR: u32 = 22_050;

fn note(onset_s: f64, offset_s: f64, midi: u8, bow_change: bool) -> TimedNote {
    TimedNote {
        note: Note::new(onset_s, offset_s, midi),
        bow_change,
        dynamic: 0.7,
        accent: false,
    }
}

fn timeline(notes: Vec<TimedNote>) -> Timeline {
    Timeline {
        duration_s: 3.0,
        notes,
        beats_s: vec![],
        downbeats_s: vec![],
        arousal_2hz: vec![0.0; 6],
        tempo_bpm: 120.0,
    }
}

fn rms(a: &[f32], t0: f64, t1: f64) -> f64 {
    let (i0, i1) = ((t0 * f64::from(SR)) as usize, (t1 * f64::from(SR)) as usize);
    (a[i0..i1].iter().map(|x| f64::from(*x).powi(2)).sum::<f64>() / (i1 - i0) as f64).sqrt()
}

/// Dominant period by autocorrelation over a window, in Hz.
fn pitch_hz(a: &[f32], t0: f64, t1: f64) -> f64 {
    let (i0, i1) = ((t0 * f64::from(SR)) as usize, (t1 * f64::from(SR)) as usize);
    let x = &a[i0..i1];
    let best = (20..400)
        .max_by(|&p, &q| {
            let c = |lag: usize| x.iter().zip(&x[lag..]).map(|(u, v)| u * v).sum::<f32>();
            c(p).total_cmp(&c(q))
        })
        .unwrap();
    f64::from(SR) / best as f64
}

fn render(notes: Vec<TimedNote>) -> Vec<f32> {
    let r = SoundFontRenderer::from_bytes(&tiny_violin_sf2()).unwrap();
    let settings = RenderSettings {
        sample_rate_hz: SR,
        tuning_cents: 0.0,
        seed: 3,
    };
    r.render(&timeline(notes), &settings).unwrap()
}

#[test]
fn bow_change_reattacks_and_slur_glides() {
    // A3 then C4: once slurred, once with a bow change.
    let slurred = render(vec![note(0.2, 1.0, 57, true), note(1.0, 1.8, 60, false)]);
    let changed = render(vec![note(0.2, 0.97, 57, true), note(1.0, 1.8, 60, true)]);
    let dip = |a: &[f32]| {
        let low = (0..8)
            .map(|k| rms(a, 0.97 + 0.005 * f64::from(k), 0.975 + 0.005 * f64::from(k)))
            .fold(f64::MAX, f64::min);
        low / rms(a, 0.8, 0.9)
    };
    let (d_slur, d_change) = (dip(&slurred), dip(&changed));
    println!("dip ratio: slurred {d_slur:.2}, bow change {d_change:.2}");
    assert!(d_slur > 0.7, "{d_slur}");
    assert!(d_change < 0.5, "{d_change}");
    // A4 twice under one bow: portato, the level dips at the second onset (no tie).
    let portato = render(vec![note(0.2, 1.0, 57, true), note(1.0, 1.8, 57, false)]);
    let d_portato = dip(&portato);
    println!("dip ratio: portato {d_portato:.2}");
    assert!(d_portato < 0.6, "{d_portato}");
    // Both reach the right pitches (within 3 %).
    for a in [&slurred, &changed] {
        let p1 = pitch_hz(a, 0.5, 0.8);
        let p2 = pitch_hz(a, 1.3, 1.6);
        assert!((p1 / 220.0 - 1.0).abs() < 0.03, "{p1}");
        assert!((p2 / 261.63 - 1.0).abs() < 0.03, "{p2}");
    }
    // Silence after the last note's release.
    assert!(rms(&slurred, 2.5, 2.9) < 1e-3);
}

#[test]
fn bad_soundfonts_are_errors() {
    assert!(matches!(
        SoundFontRenderer::from_bytes(b"RIFF1234notasoundfont"),
        Err(RenderError::SoundFont(_))
    ));
    let mut cut = tiny_violin_sf2();
    cut.truncate(cut.len() / 2);
    assert!(SoundFontRenderer::from_bytes(&cut).is_err());
    let err = SoundFontRenderer::from_file("/no/such/font.sf2").unwrap_err();
    assert!(err.to_string().contains("/no/such/font.sf2"));
}
