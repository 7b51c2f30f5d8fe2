//! Accuracy on synthetic violin — corpus études rendered by the corpus's bowed-string
//! synthesizer — raw pitch accuracy and note onsets; vibrato, repeated notes, glides, silence
//! and bad input on generated tones.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use corpus::etude::EtudeConfig;
use corpus::item::{clean_etude, CorpusItem};
use corpus::reference::reference_f0;
use pitch_track::eval::{melody_scores, onset_prf, MelodyScores};
use pitch_track::{
    segment_notes, Note, NoteConfig, PitchConfig, PitchError, PitchTrack, PitchTracker,
};

/// Corpus item `seed` (an étude of about `seconds`), built-in renderer, no augmentation
/// (22 050 Hz, no tuning offset).
fn item(seed: u64, seconds: f64) -> CorpusItem {
    clean_etude(seed, seconds, EtudeConfig::default().tempo_bpm).unwrap()
}

fn analyse(samples: &[f32]) -> (PitchTrack, Vec<Note>) {
    let tracker = PitchTracker::new(PitchConfig::default()).unwrap();
    let track = tracker.track(samples).unwrap();
    let notes = segment_notes(&track, samples, 22_050, &NoteConfig::default()).unwrap();
    (track, notes)
}

/// mir_eval melody scores of `f0_hz` (NaN = unvoiced) on the `hop_s` grid against the
/// item's labelled notes, on the frames the labels decide.
fn melody_against(item: &CorpusItem, f0_hz: &[f32], hop_s: f64) -> MelodyScores {
    let reference = reference_f0(&item.timeline, 0.0, hop_s, f0_hz.len());
    let (r, e): (Vec<f32>, Vec<f32>) = reference
        .iter()
        .zip(f0_hz)
        .filter_map(|(r, e)| r.map(|r| (r, if e.is_finite() { *e } else { 0.0 })))
        .unzip();
    melody_scores(&r, &e, 50.0).unwrap()
}

#[test]
fn varied_pieces_meet_the_accuracy_goals() {
    let (mut rpa_sum, mut f_sum, mut n) = (0.0, 0.0, 0.0);
    for seed in 1..=4 {
        let item = item(seed, 16.0);
        let (track, notes) = analyse(&item.audio);
        let melody = melody_against(&item, &track.f0_hz, track.hop_s);
        let ref_on: Vec<f64> = item.timeline.notes.iter().map(|n| n.note.onset_s).collect();
        let est_on: Vec<f64> = notes.iter().map(|n| n.onset_s).collect();
        let onsets = onset_prf(&ref_on, &est_on, 0.05);
        println!(
            "seed {seed}: {:.0} bpm {}: RPA {:.4} VR {:.3} VFA {:.3} onset P {:.3} R {:.3} F {:.3} ({} ref, {} est)",
            item.timeline.tempo_bpm, item.time_signature, melody.raw_pitch_accuracy, melody.voicing_recall,
            melody.voicing_false_alarm, onsets.precision, onsets.recall, onsets.f_measure, ref_on.len(), est_on.len()
        );
        rpa_sum += melody.raw_pitch_accuracy;
        f_sum += onsets.f_measure;
        n += 1.0;
    }
    println!("mean RPA {:.4}, mean onset F {:.4}", rpa_sum / n, f_sum / n);
    assert!(rpa_sum / n >= 0.97, "raw pitch accuracy {}", rpa_sum / n);
    assert!(f_sum / n >= 0.90, "onset F {}", f_sum / n);
}

#[test]
fn vibrato_does_not_split_a_long_note() {
    let sr = 22_050usize;
    // 2 s of A4 with ±50 cents vibrato at 5 and at 7 Hz.
    for rate in [5.0f64, 7.0] {
        let mut phase = 0.0f64;
        let x: Vec<f32> = (0..2 * sr)
            .map(|i| {
                let t = i as f64 / sr as f64;
                let f = 440.0 * (50.0 * (std::f64::consts::TAU * rate * t).sin() / 1200.0).exp2();
                phase += std::f64::consts::TAU * f / sr as f64;
                (0.5 * (phase.sin() + 0.5 * (2.0 * phase).sin() + 0.3 * (3.0 * phase).sin())) as f32
            })
            .collect();
        let track = PitchTracker::new(PitchConfig::default())
            .unwrap()
            .track(&x)
            .unwrap();
        let notes = segment_notes(&track, &x, sr as u32, &NoteConfig::default()).unwrap();
        assert_eq!(notes.len(), 1, "{rate} Hz vibrato: {notes:?}");
        assert_eq!(notes[0].midi, 69);
        assert!(notes[0].offset_s - notes[0].onset_s > 1.8);
    }
}

/// SplitMix64 with Box–Muller normals: the seeded noise of the bow-change bursts below.
struct SplitMix64(u64);

impl SplitMix64 {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn normal(&mut self) -> f64 {
        let u1 = self.unit().max(1e-300);
        let u2 = self.unit();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

/// A tone with a bow change (dip + noise burst) or a slur at each boundary.
fn tone_sequence(pitches: &[(f64, bool)], note_s: f64, glide_s: f64) -> Vec<f32> {
    let sr = 22_050.0;
    let mut rng = SplitMix64(5);
    let mut out = Vec::new();
    let mut phase = 0.0f64;
    let mut prev: Option<f64> = None;
    for &(midi, slurred) in pitches {
        let hz = 440.0 * ((midi - 69.0) / 12.0).exp2();
        for i in 0..(note_s * sr) as usize {
            let t = i as f64 / sr;
            let f = match (slurred, prev) {
                (true, Some(p)) if t < glide_s => p * (hz / p).powf(t / glide_s),
                _ => hz,
            };
            phase += std::f64::consts::TAU * f / sr;
            let mut amp = 0.5;
            if !slurred {
                amp *= 0.25 + 0.75 * (1.0 - (-t / 0.025).exp());
                if note_s - t < 0.03 {
                    amp *= 0.25 + 0.75 * (note_s - t) / 0.03;
                }
            }
            let burst = if !slurred && t < 0.05 {
                0.2 * (-t / 0.015).exp() * rng.normal()
            } else {
                0.0
            };
            out.push(
                (amp * (phase.sin() + 0.5 * (2.0 * phase).sin() + 0.3 * (3.0 * phase).sin())
                    + burst) as f32,
            );
        }
        prev = Some(hz);
    }
    out
}

#[test]
fn repeated_notes_are_split_at_bow_changes() {
    let x = tone_sequence(
        &[(69.0, false), (69.0, false), (69.0, false), (72.0, false)],
        0.4,
        0.0,
    );
    let track = PitchTracker::new(PitchConfig::default())
        .unwrap()
        .track(&x)
        .unwrap();
    let notes = segment_notes(&track, &x, 22_050, &NoteConfig::default()).unwrap();
    let midis: Vec<u8> = notes.iter().map(|n| n.midi).collect();
    assert_eq!(midis, vec![69, 69, 69, 72], "{notes:?}");
    let onsets: Vec<f64> = notes.iter().map(|n| n.onset_s).collect();
    let f = onset_prf(&[0.0, 0.4, 0.8, 1.2], &onsets, 0.05).f_measure;
    assert!(f >= 0.99, "{onsets:?}");
}

#[test]
fn slurred_glides_do_not_create_short_notes() {
    // A slurred scale with 60 ms glides across a third (passing through the semitones between).
    let x = tone_sequence(
        &[
            (67.0, false),
            (71.0, true),
            (74.0, true),
            (71.0, true),
            (67.0, true),
        ],
        0.35,
        0.06,
    );
    let track = PitchTracker::new(PitchConfig::default())
        .unwrap()
        .track(&x)
        .unwrap();
    let notes = segment_notes(&track, &x, 22_050, &NoteConfig::default()).unwrap();
    let midis: Vec<u8> = notes.iter().map(|n| n.midi).collect();
    assert_eq!(midis, vec![67, 71, 74, 71, 67], "{notes:?}");
    assert!(notes.iter().all(|n| n.offset_s - n.onset_s >= 0.07));
}

#[test]
fn silence_gives_no_notes_and_no_panic() {
    let x = vec![0.0f32; 22_050];
    let (track, notes) = {
        let t = PitchTracker::new(PitchConfig::default())
            .unwrap()
            .track(&x)
            .unwrap();
        let n = segment_notes(&t, &x, 22_050, &NoteConfig::default()).unwrap();
        (t, n)
    };
    assert_eq!(track.voiced_count(), 0);
    assert!(notes.is_empty());
    assert!(track.f0_hz.iter().all(|f| f.is_nan()));
}

#[test]
fn short_audio_gives_a_short_result_not_a_panic() {
    let sr = 22_050usize;
    let x: Vec<f32> = (0..sr / 10).map(|i| (i as f32 * 0.1).sin()).collect(); // 0.1 s
    let track = PitchTracker::new(PitchConfig::default())
        .unwrap()
        .track(&x)
        .unwrap();
    assert_eq!(track.len(), 1 + x.len() / 256);
    let notes = segment_notes(&track, &x, sr as u32, &NoteConfig::default()).unwrap();
    assert!(notes.len() <= 1);
    let one = PitchTracker::new(PitchConfig::default())
        .unwrap()
        .track(&[0.3])
        .unwrap();
    assert_eq!(one.len(), 1);
}

#[test]
fn bad_input_is_a_typed_error() {
    let tracker = PitchTracker::new(PitchConfig::default()).unwrap();
    assert!(matches!(tracker.track(&[]), Err(PitchError::EmptyAudio)));
    assert!(matches!(
        tracker.track(&[0.0, 1.0, f32::NAN]),
        Err(PitchError::NonFinite { index: 2 })
    ));
    assert!(matches!(
        tracker.track(&[f32::INFINITY]),
        Err(PitchError::NonFinite { index: 0 })
    ));
    let track = PitchTrack {
        hop_s: 256.0 / 22_050.0,
        f0_hz: vec![440.0; 3],
        voiced_prob: vec![1.0; 3],
    };
    assert!(segment_notes(&track, &[0.0, f32::NAN], 22_050, &NoteConfig::default()).is_err());
    assert!(PitchTracker::new(PitchConfig {
        fmin_hz: -1.0,
        ..PitchConfig::default()
    })
    .is_err());
}

#[test]
fn resampling_to_30_fps_keeps_the_pitch() {
    let item = item(2, 6.0);
    let (track, _) = analyse(&item.audio);
    let at30 = track.resample_to_fps(30.0);
    assert!((at30.hop_s - 1.0 / 30.0).abs() < 1e-12);
    let span = (track.len() - 1) as f64 * track.hop_s;
    assert_eq!(at30.len(), (span * 30.0).floor() as usize + 1);
    let s = melody_against(&item, &at30.f0_hz, at30.hop_s);
    println!("30 fps: {s:?}");
    assert!(s.raw_pitch_accuracy > 0.95, "{s:?}");
}
