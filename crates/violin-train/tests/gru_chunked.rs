#![allow(clippy::unwrap_used, clippy::expect_used)]
//! Chunked inference (a recording cut into chunks that run side by side, each starting a
//! warm-up early from a zero state) against the sequential run, on rendered violin audio
//! with the shipped weights. The tolerance is the one measured on corpus-mix's test split (crate
//! README, "Speed"): mean 0.016 px, 99th percentile 0.30 px, largest 2.7 px.

use corpus::etude::EtudeConfig;
use corpus::item::{make_item, RendererKind};
use corpus::render::BowedStringSynth;
use gru_baseline::features::mel_frames;
use gru_baseline::{Chunking, GruBaseline};

#[test]
fn chunked_inference_matches_the_sequential_run() {
    let etude = EtudeConfig {
        target_s: 45.0,
        ..EtudeConfig::default()
    };
    let item = make_item(
        21,
        &etude,
        &BowedStringSynth::default(),
        RendererKind::Builtin,
        true,
    )
    .unwrap();
    let audio = dsp_mel::Audio::new(item.audio, item.augmentation.sample_rate_hz).unwrap();
    let mel = mel_frames(&audio).unwrap();
    let net = GruBaseline::pretrained().unwrap();
    let sequential = net.predict_normalized_exact(mel.view()).unwrap();
    let chunking = Chunking::default();
    let chunks = chunking
        .plan(&vec![true; mel.nrows() + net.config().lookahead_frames])
        .unwrap();
    assert!(chunks.len() >= 4, "{} chunks", chunks.len());
    let chunked = net.predict_normalized_with(mel.view(), &chunking).unwrap();
    assert_eq!(chunked.dim(), sequential.dim());
    let torso_px = net.target_space().torso_px;
    let diffs: Vec<f32> = (&chunked - &sequential)
        .iter()
        .map(|d| d.abs() * torso_px)
        .collect();
    let mean = diffs.iter().sum::<f32>() / diffs.len() as f32;
    let max = diffs.iter().copied().fold(0.0, f32::max);
    assert!(mean < MEAN_TOLERANCE_PX, "mean |diff| {mean} px");
    assert!(max < MAX_TOLERANCE_PX, "max |diff| {max} px");
    // The default (a shorter recording is one chunk) is the sequential run itself.
    let short = mel.slice(ndarray::s![..200, ..]);
    assert_eq!(
        net.predict_normalized(short).unwrap(),
        net.predict_normalized_exact(short).unwrap()
    );
}

const MEAN_TOLERANCE_PX: f32 = 0.05;
const MAX_TOLERANCE_PX: f32 = 3.0;
