#![allow(clippy::unwrap_used, clippy::expect_used)]
//! Per-recording level normalisation: a louder copy of a recording gives the same arousal,
//! older weights files read as absolute levels, and bad quantiles are refused.

mod common;

use emotion_net::estimator::predict_with;
use emotion_net::model::{Config, EmotionNet, GainNorm};
use ndarray::Array2;

fn net(gain_norm: GainNorm) -> EmotionNet {
    let cfg = Config {
        gain_norm,
        ..Config::default()
    };
    // As the trainer initialises: biases 0, batch-norm scale and shift untouched.
    common::seeded_net(
        &cfg,
        3,
        &common::Keep {
            containing: &["gamma", "beta"],
            zero_biases: true,
        },
    )
    .1
}

fn mel(frames: usize) -> Array2<f32> {
    Array2::from_shape_fn((frames, 64), |(t, b)| {
        -1.5 + 2.0 * ((t as f32 * 0.37).sin() * (b as f32 * 0.11).cos()).abs()
    })
}

#[test]
fn track_quantile_makes_the_output_independent_of_the_recording_gain() {
    // Small values: the network's normalisation is the identity here, and larger inputs
    // would saturate the randomly initialised output at the clamp.
    let quiet = mel(57);
    let loud = &quiet + 1.5;
    let normalised = net(GainNorm::TrackQuantile(0.95));
    let a = predict_with(&normalised, quiet.view()).unwrap();
    let b = predict_with(&normalised, loud.view()).unwrap();
    assert_eq!(a.len(), 57);
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() < 1e-4, "{x} vs {y}");
    }
    // Absolute levels do see the gain.
    let absolute = net(GainNorm::Absolute);
    let a = predict_with(&absolute, quiet.view()).unwrap();
    let b = predict_with(&absolute, loud.view()).unwrap();
    assert!(
        a.iter().zip(&b).any(|(x, y)| (x - y).abs() > 1e-3),
        "{a:?} vs {b:?}"
    );
}

#[test]
fn offset_is_the_frame_loudness_quantile() {
    // One band at d dB and the rest far below: the frame loudness is d.
    let mut m = Array2::from_elem((5, 64), -200.0f32);
    for (t, d) in [-30.0, -10.0, -20.0, -40.0, 0.0].into_iter().enumerate() {
        m[[t, 7]] = d;
    }
    assert!((GainNorm::TrackQuantile(1.0).offset_db(m.view()) - 0.0).abs() < 1e-3);
    assert!((GainNorm::TrackQuantile(0.5).offset_db(m.view()) + 20.0).abs() < 1e-3);
    assert!((GainNorm::TrackQuantile(0.0).offset_db(m.view()) + 40.0).abs() < 1e-3);
    assert_eq!(GainNorm::Absolute.offset_db(m.view()), 0.0);
    // Empty and NaN-only inputs give no offset rather than a NaN.
    let empty = Array2::<f32>::zeros((0, 64));
    assert_eq!(GainNorm::TrackQuantile(0.9).offset_db(empty.view()), 0.0);
    let nan = Array2::from_elem((3, 64), f32::NAN);
    assert_eq!(GainNorm::TrackQuantile(0.9).offset_db(nan.view()), 0.0);
}

#[test]
fn configs_without_the_field_read_as_absolute_and_bad_quantiles_are_refused() {
    let old: Config = serde_json::from_str(r#"{"steps": 20, "conv_dropout": 0.75}"#).unwrap();
    assert_eq!(old.gain_norm, GainNorm::Absolute);
    let new: Config = serde_json::from_str(r#"{"gain_norm": {"track_quantile": 0.95}}"#).unwrap();
    assert_eq!(new.gain_norm, GainNorm::TrackQuantile(0.95));
    // A field from a newer network is refused, not ignored.
    assert!(serde_json::from_str::<Config>(r#"{"attention_heads": 4}"#).is_err());
    for q in [1.5f32, -0.1, f32::NAN] {
        let cfg = Config {
            gain_norm: GainNorm::TrackQuantile(q),
            ..Config::default()
        };
        assert!(cfg.validate().is_err(), "{q}");
    }
}
