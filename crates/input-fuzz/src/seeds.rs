//! The seed inputs of every kind, made here from the project's own writers (motion files,
//! OpenPose frames, analysis and performance JSON, weights) and the audio fixtures of dsp-mel.

use std::io::Cursor;
use std::path::Path;

use violin_skeleton::{Motion, MotionFormat, Pipeline};

use crate::targets::Kind;

/// Bytes of the shipped audio fixtures (dsp-mel's parity tests use the same files).
const FLAC: &[u8] = include_bytes!("../../dsp-mel/tests/fixtures/audio/a440_22050_1ch.flac");
const MP3: &[u8] = include_bytes!("../../dsp-mel/tests/fixtures/audio/a440_44100_1ch.mp3");
const OGG: &[u8] = include_bytes!("../../dsp-mel/tests/fixtures/audio/a440_44100_2ch.ogg");
const WAV_F32: &[u8] = include_bytes!("../../dsp-mel/tests/fixtures/audio/a440_16000_1ch.f32.wav");

/// A 16-bit WAV: 1.5 s of a bowed-like tone (sawtooth, 8 notes, vibrato) at 22 050 Hz.
pub fn wav16() -> Vec<u8> {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 22_050,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut bytes = Cursor::new(Vec::new());
    if let Ok(mut w) = hound::WavWriter::new(&mut bytes, spec) {
        let n = 22_050 * 3 / 2;
        let mut phase = 0.0f64;
        for i in 0..n {
            let t = i as f64 / 22_050.0;
            let note = (t / 0.1875) as usize % 8;
            let f0 = 440.0 * 2f64.powf([0, 2, 4, 5, 7, 5, 4, 2][note] as f64 / 12.0);
            phase = (phase
                + f0 * (1.0 + 0.004 * (2.0 * std::f64::consts::PI * 5.5 * t).sin()) / 22_050.0)
                .fract();
            let v = (2.0 * phase - 1.0) * 0.3 * (1.0 - (-(t % 0.1875) * 40.0).exp());
            let _ = w.write_sample((v * 32767.0) as i16);
        }
        let _ = w.finalize();
    }
    bytes.into_inner()
}

/// A format-0 Standard MIDI File: 120 bpm, 3/4, a slurred scale of 12 notes with velocities,
/// the fifth one (D5) with F#4 under it (a double stop, so the second voice is fuzzed too).
pub fn midi() -> Vec<u8> {
    let mut track: Vec<u8> = Vec::new();
    // tempo 500 000 µs per quarter, time signature 3/4.
    track.extend_from_slice(&[0x00, 0xFF, 0x51, 0x03, 0x07, 0xA1, 0x20]);
    track.extend_from_slice(&[0x00, 0xFF, 0x58, 0x04, 0x03, 0x02, 0x18, 0x08]);
    for (k, key) in [67u8, 69, 71, 72, 74, 76, 78, 79, 81, 83, 84, 86]
        .iter()
        .enumerate()
    {
        let velocity = 60 + (k as u8 * 5) % 50;
        track.extend_from_slice(&[0x00, 0x90, *key, velocity]);
        if k == 4 {
            track.extend_from_slice(&[0x00, 0x90, 66, velocity]);
        }
        // 240 ticks (an eighth at 480 per quarter), as a two-byte variable-length number.
        track.extend_from_slice(&[0x81, 0x70, 0x80, *key, 0x40]);
        if k == 4 {
            track.extend_from_slice(&[0x00, 0x80, 66, 0x40]);
        }
    }
    track.extend_from_slice(&[0x00, 0xFF, 0x2F, 0x00]);
    let mut smf = b"MThd\x00\x00\x00\x06\x00\x00\x00\x01\x01\xE0MTrk".to_vec();
    smf.extend_from_slice(&(track.len() as u32).to_be_bytes());
    smf.extend_from_slice(&track);
    smf
}

/// Everything the seeds of the motion, OpenPose and JSON kinds are made from.
pub struct SeedSet {
    /// Seeds per kind: the first is mutated, the rest are splice partners.
    pub by_kind: Vec<(Kind, Vec<Vec<u8>>)>,
    /// The OpenPose frames of the seed motion (file name, bytes), the folder around a mutant.
    pub openpose_frames: Vec<(String, Vec<u8>)>,
}

fn read_back(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_default()
}

/// Builds every seed (about a second: one MIDI file through the pipeline).
pub fn seed_set(scratch: &Path) -> Result<SeedSet, String> {
    let mid = scratch.join("seed.mid");
    std::fs::write(&mid, midi()).map_err(|e| e.to_string())?;
    let pipeline = Pipeline::default();
    let analysis = pipeline
        .analyze_midi_file(&mid)
        .map_err(|e| e.to_string())?;
    let perf = pipeline
        .performance_from_midi(&mid)
        .map_err(|e| e.to_string())?;
    let motion = pipeline.generate_midi(&mid).map_err(|e| e.to_string())?;
    // Two seconds of motion keep each OpenPose mutant cheap.
    let short = Motion::new(
        motion.fps(),
        motion
            .frames()
            .slice(ndarray::s![..motion.len().min(60), .., ..])
            .to_owned(),
    )
    .map_err(|e| e.to_string())?;
    let mut motion_files = Vec::new();
    for (ext, format) in [
        ("json", MotionFormat::Json),
        ("csv", MotionFormat::Csv),
        ("npy", MotionFormat::Npy),
    ] {
        let p = scratch.join(format!("seed.{ext}"));
        short.write(&p, format).map_err(|e| e.to_string())?;
        motion_files.push(read_back(&p));
    }
    let pose_dir = scratch.join("seed_openpose");
    short
        .write_openpose(&pose_dir, &Default::default())
        .map_err(|e| e.to_string())?;
    let mut openpose_frames: Vec<(String, Vec<u8>)> = std::fs::read_dir(&pose_dir)
        .map_err(|e| e.to_string())?
        .filter_map(|e| e.ok())
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                read_back(&e.path()),
            )
        })
        .collect();
    openpose_frames.sort();
    let analysis_json = serde_json::to_vec(&analysis).map_err(|e| e.to_string())?;
    let perf_json = serde_json::to_vec(&perf).map_err(|e| e.to_string())?;
    let weights = |r: Result<Vec<u8>, String>| r.unwrap_or_default();
    let bowing = weights(
        violin_skeleton::bowing_net::BowingModel::pretrained_strokes()
            .and_then(|d| d.to_bytes())
            .map_err(|e| e.to_string()),
    );
    let cnn = weights(
        violin_skeleton::bowing_net::BowChangeDetector::pretrained()
            .and_then(|d| d.to_bytes())
            .map_err(|e| e.to_string()),
    );
    let beat = weights(
        beat_net::BeatActivation::pretrained()
            .and_then(|d| d.to_bytes())
            .map_err(|e| e.to_string()),
    );
    let emotion = weights(
        violin_skeleton::emotion_net::ArousalEstimator::pretrained()
            .and_then(|d| d.to_bytes())
            .map_err(|e| e.to_string()),
    );
    let wav = wav16();
    let by_kind = vec![
        (Kind::Wav, vec![wav.clone(), WAV_F32.to_vec()]),
        (Kind::Flac, vec![FLAC.to_vec(), wav.clone()]),
        (Kind::Mp3, vec![MP3.to_vec(), OGG.to_vec()]),
        (Kind::Ogg, vec![OGG.to_vec(), MP3.to_vec()]),
        (Kind::Midi, vec![midi(), midi()]),
        (
            Kind::OpenPose,
            vec![
                openpose_frames
                    .get(openpose_frames.len() / 2)
                    .map(|f| f.1.clone())
                    .unwrap_or_default(),
                motion_files[0].clone(),
            ],
        ),
        (
            Kind::MotionJson,
            vec![motion_files[0].clone(), analysis_json.clone()],
        ),
        (
            Kind::MotionCsv,
            vec![motion_files[1].clone(), motion_files[0].clone()],
        ),
        (
            Kind::MotionNpy,
            vec![motion_files[2].clone(), motion_files[1].clone()],
        ),
        (Kind::BowingWeights, vec![bowing, cnn.clone()]),
        (Kind::BeatWeights, vec![beat, cnn]),
        (Kind::EmotionWeights, vec![emotion.clone(), emotion]),
        (Kind::AnalysisJson, vec![analysis_json, perf_json.clone()]),
        (Kind::PerformanceJson, vec![perf_json.clone(), perf_json]),
    ];
    Ok(SeedSet {
        by_kind,
        openpose_frames,
    })
}
