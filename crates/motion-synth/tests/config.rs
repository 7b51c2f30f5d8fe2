//! Synthesis settings out of range are refused.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use motion_synth::{synthesize, SynthConfig, SynthError};
use performance::Performance;

#[test]
fn bad_configs_are_rejected() {
    let p = Performance::builder(2.0)
        .note(0.0, 1.0, 67)
        .build()
        .unwrap();
    let cfg = SynthConfig {
        fps: 0.0,
        ..SynthConfig::default()
    };
    assert!(matches!(
        synthesize(&p, &cfg),
        Err(SynthError::InvalidConfig(_))
    ));
    let mut cfg = SynthConfig::default();
    cfg.camera.focal_px = f64::NAN;
    assert!(matches!(
        synthesize(&p, &cfg),
        Err(SynthError::InvalidConfig(_))
    ));
    let mut cfg = SynthConfig::default();
    cfg.bow.resolution = 1;
    assert!(matches!(
        synthesize(&p, &cfg),
        Err(SynthError::InvalidConfig(_))
    ));
}
