//! The input kinds and what each mutant goes through: the same calls the CLI makes when a
//! user hands it such a file, and for an accepted file the next stage after it (analysis of
//! decoded audio, motion from a MIDI or analysis file, a picture of a motion, a forward pass
//! of loaded weights), so values that parse but make no sense are exercised too.

use std::path::Path;

use violin_skeleton::{load_audio, Motion, MotionFormat, Performance, Pipeline};

/// One kind of user input.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    /// PCM WAV (16-bit and float).
    Wav,
    /// FLAC.
    Flac,
    /// MP3.
    Mp3,
    /// Ogg Vorbis.
    Ogg,
    /// Standard MIDI File.
    Midi,
    /// One OpenPose `*_keypoints.json` frame inside a folder of good frames (`pose-labels`,
    /// and `render` of an OpenPose folder).
    OpenPose,
    /// Motion JSON.
    MotionJson,
    /// Motion CSV.
    MotionCsv,
    /// Motion NPY.
    MotionNpy,
    /// Bowing weights (`--bowing-weights`, stroke network or CNN).
    BowingWeights,
    /// beat-net weights.
    BeatWeights,
    /// Arousal CRNN weights (`--emotion-weights`).
    EmotionWeights,
    /// `analysis.json` (`analyze -o`), read back as a performance and turned into motion.
    AnalysisJson,
    /// Performance JSON.
    PerformanceJson,
}

impl Kind {
    /// Every kind, in report order.
    pub const ALL: [Kind; 14] = [
        Kind::Wav,
        Kind::Flac,
        Kind::Mp3,
        Kind::Ogg,
        Kind::Midi,
        Kind::OpenPose,
        Kind::MotionJson,
        Kind::MotionCsv,
        Kind::MotionNpy,
        Kind::BowingWeights,
        Kind::BeatWeights,
        Kind::EmotionWeights,
        Kind::AnalysisJson,
        Kind::PerformanceJson,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Wav => "wav",
            Kind::Flac => "flac",
            Kind::Mp3 => "mp3",
            Kind::Ogg => "ogg",
            Kind::Midi => "midi",
            Kind::OpenPose => "openpose",
            Kind::MotionJson => "motion-json",
            Kind::MotionCsv => "motion-csv",
            Kind::MotionNpy => "motion-npy",
            Kind::BowingWeights => "bowing-weights",
            Kind::BeatWeights => "beat-weights",
            Kind::EmotionWeights => "emotion-weights",
            Kind::AnalysisJson => "analysis-json",
            Kind::PerformanceJson => "performance-json",
        }
    }

    /// The kind a command-line name names.
    pub fn from_name(name: &str) -> Option<Kind> {
        Kind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// `true` for the JSON kinds, which also get structure-aware mutants.
    pub fn is_json(self) -> bool {
        matches!(
            self,
            Kind::OpenPose | Kind::MotionJson | Kind::AnalysisJson | Kind::PerformanceJson
        )
    }

    /// The file name a mutant is written under.
    pub fn file_name(self) -> &'static str {
        match self {
            Kind::Wav => "input.wav",
            Kind::Flac => "input.flac",
            Kind::Mp3 => "input.mp3",
            Kind::Ogg => "input.ogg",
            Kind::Midi => "input.mid",
            Kind::OpenPose => "take_000000000030_keypoints.json",
            Kind::MotionJson | Kind::AnalysisJson | Kind::PerformanceJson => "input.json",
            Kind::MotionCsv => "input.csv",
            Kind::MotionNpy => "input.npy",
            Kind::BowingWeights | Kind::BeatWeights | Kind::EmotionWeights => "input.safetensors",
        }
    }
}

/// A small log-mel input (64 frames × 128 bands, dB-like values) for forward passes.
fn test_mel() -> ndarray::Array2<f32> {
    ndarray::Array2::from_shape_fn((64, 128), |(t, b)| -60.0 + ((t * 7 + b * 3) % 50) as f32)
}

/// Runs one mutant already written at `file` (for [`Kind::OpenPose`], inside folder `dir`
/// with the other frames). `Ok` when the input was accepted, `Err` with the message a user
/// would read when it was refused.
pub fn run(kind: Kind, file: &Path, dir: &Path, pipeline: &Pipeline) -> Result<(), String> {
    let s = |e: &dyn std::fmt::Display| e.to_string();
    match kind {
        Kind::Wav | Kind::Flac | Kind::Mp3 | Kind::Ogg => {
            let audio = load_audio(file).map_err(|e| s(&e))?;
            pipeline.analyze(&audio).map_err(|e| s(&e))?;
        }
        Kind::Midi => {
            pipeline.analyze_midi_file(file).map_err(|e| s(&e))?;
            pipeline.generate_midi(file).map_err(|e| s(&e))?;
        }
        Kind::OpenPose => {
            pose_preproc::preprocess_dir(dir, &pose_preproc::PreprocConfig::default())
                .map_err(|e| s(&e))?;
            let motion = Motion::read_openpose(dir, 30.0).map_err(|e| s(&e))?;
            picture(&motion)?;
        }
        Kind::MotionJson | Kind::MotionCsv | Kind::MotionNpy => {
            let format = MotionFormat::from_path(file).map_err(|e| s(&e))?;
            let motion = Motion::read(file, format).map_err(|e| s(&e))?;
            picture(&motion)?;
        }
        Kind::BowingWeights => {
            let model = violin_skeleton::networks::load_bowing(file).map_err(|e| s(&e))?;
            violin_skeleton::networks::bowing_of_mel(&model, test_mel().view())
                .map_err(|e| s(&e))?;
        }
        Kind::BeatWeights => {
            let net = beat_net::BeatActivation::load(file).map_err(|e| s(&e))?;
            net.activations(test_mel().view()).map_err(|e| s(&e))?;
        }
        Kind::EmotionWeights => {
            let net = violin_skeleton::networks::load_emotion(file).map_err(|e| s(&e))?;
            let mel2 =
                ndarray::Array2::from_shape_fn((40, 64), |(t, b)| -50.0 + ((t + b) % 30) as f32);
            net.predict(mel2.view()).map_err(|e| s(&e))?;
        }
        Kind::AnalysisJson => {
            let bytes = std::fs::read(file).map_err(|e| s(&e))?;
            let analysis: violin_skeleton::Analysis =
                serde_json::from_slice(&bytes).map_err(|e| s(&e))?;
            pipeline
                .generate_from_analysis(&analysis)
                .map_err(|e| s(&e))?;
        }
        Kind::PerformanceJson => {
            let perf = Performance::read_json(file).map_err(|e| s(&e))?;
            violin_skeleton::motion_synth::synthesize(&perf, pipeline.synth_config())
                .map_err(|e| s(&e))?;
        }
    }
    Ok(())
}

/// A picture of the motion's middle frame: what `render` does with an accepted motion.
fn picture(motion: &Motion) -> Result<(), String> {
    let cfg = violin_skeleton::skeleton_render::RenderConfig {
        width: 64,
        height: 36,
        ..Default::default()
    };
    violin_skeleton::skeleton_render::render_png(motion, motion.len() / 2, &cfg)
        .map(|_| ())
        .map_err(|e| e.to_string())
}
