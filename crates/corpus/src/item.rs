//! One corpus item: an étude, its timeline, its ground-truth `Performance`, audio and motion.

use motion_synth::{synthesize, SynthConfig};
use performance::{BowStroke, Performance, TimeSignature};
use serde::{Deserialize, Serialize};
use skeleton::Motion;

use crate::augment::Augmentation;
use crate::bow_weight::{apply_bow_weight, draw_tilt_db};
use crate::double_stop::{double_stops, mix_into, DoubleStops};
use crate::error::CorpusError;
use crate::etude::{generate, EtudeConfig};
use crate::perform::{bow_strokes, hook_to_downbeats, perform, TimingDraw};
use crate::render::{RenderSettings, Renderer};
use crate::room::Recording;
use crate::score::Score;
use crate::timing::play;
use net_core::rng::Rng;
use performance::Timeline;

/// The item seed's fork that draws the bow-weight tilt ([`crate::bow_weight`]).
const BOW_WEIGHT_FORK: u64 = 7;
/// The item seed's fork that draws where the player hooks strokes ([`hook_to_downbeats`]).
const HOOK_FORK: u64 = 8;

/// Which renderer made an item.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RendererKind {
    /// The built-in bowed-string synthesizer.
    Builtin,
    /// A SoundFont through rustysynth.
    Soundfont,
    /// The digital-waveguide bowed string.
    Waveguide,
}

impl RendererKind {
    /// "builtin", "soundfont" or "waveguide".
    pub fn name(self) -> &'static str {
        match self {
            RendererKind::Builtin => "builtin",
            RendererKind::Soundfont => "soundfont",
            RendererKind::Waveguide => "waveguide",
        }
    }
}

/// Everything made for one item, in memory.
#[derive(Debug, Clone)]
pub struct CorpusItem {
    /// The written music (an étude or a repertoire excerpt).
    pub score: Score,
    /// The étude as played (seconds, labels).
    pub timeline: Timeline,
    /// The ground-truth performance (motion-synth's input).
    pub performance: Performance,
    /// Ground-truth motion synthesised from the performance.
    pub motion: Motion,
    /// Audio at `augmentation.sample_rate_hz`: mono, or the first channel of a stereo
    /// recording.
    pub audio: Vec<f32>,
    /// Further channels (the second microphone of a stereo [`Recording`]).
    pub extra_channels: Vec<Vec<f32>>,
    /// The recording chain applied (many-violin corpora), including any lossy coding that
    /// [`crate::layout::write_item`] performs.
    pub recording: Option<Recording>,
    /// How the audio was augmented.
    pub augmentation: Augmentation,
    /// Which renderer made the audio.
    pub renderer: RendererKind,
    /// Bow strokes with direction and string.
    pub strokes: Vec<BowStroke>,
    /// The main time signature.
    pub time_signature: TimeSignature,
    /// Local tempo at each beat, notated beats per minute.
    pub tempo_bpm_per_beat: Vec<f64>,
    /// How the performance was timed (`None` for the gentle étude player).
    pub timing: Option<TimingDraw>,
    /// The second notes of the score's double stops, rendered under the melody.
    pub double_stops: DoubleStops,
}

/// The timeline as a validated [`Performance`] with fingering and dynamics.
pub fn performance_of(timeline: &Timeline) -> Result<Performance, CorpusError> {
    timeline
        .to_performance()
        .map_err(|e| CorpusError::Performance(e.to_string()))
}

/// Makes item `seed` with `renderer`: étude → timeline (fingered by the optimal planner) →
/// performance → motion; audio rendered with a seeded [`Augmentation`] (or none).
pub fn make_item(
    seed: u64,
    etude_cfg: &EtudeConfig,
    renderer: &dyn Renderer,
    kind: RendererKind,
    augment: bool,
) -> Result<CorpusItem, CorpusError> {
    let root = Rng::new(seed);
    let etude = generate(root.fork(1).next_u64(), etude_cfg);
    let mut timeline = play(&etude, root.fork(2).next_u64());
    timeline.assign_fingering(&fingering::OptimalPlanner::default());
    let performance = performance_of(&timeline)?;
    let motion = synthesize(&performance, &SynthConfig::default())
        .map_err(|e| CorpusError::Performance(e.to_string()))?;
    let mut aug_rng = root.fork(3);
    let augmentation = if augment {
        Augmentation::draw(&mut aug_rng)
    } else {
        Augmentation::none(22_050)
    };
    let settings = RenderSettings {
        sample_rate_hz: augmentation.sample_rate_hz,
        tuning_cents: augmentation.tuning_cents,
        seed: root.fork(4).next_u64(),
    };
    let mut audio = renderer.render(&timeline, &settings)?;
    let strokes = bow_strokes(&timeline);
    let tilt_db = draw_tilt_db(&mut root.fork(BOW_WEIGHT_FORK));
    apply_bow_weight(&mut audio, settings.sample_rate_hz, &strokes, tilt_db);
    augmentation.apply(&mut audio, root.fork(5).next_u64());
    let tempo_bpm_per_beat = timeline
        .beats_s
        .windows(2)
        .map(|w| 60.0 / (w[1] - w[0]).max(1e-6))
        .collect();
    Ok(CorpusItem {
        score: etude.to_score(&format!("etude/{seed}")),
        time_signature: etude.meter.time_signature(),
        timeline,
        performance,
        motion,
        audio,
        augmentation,
        renderer: kind,
        strokes,
        tempo_bpm_per_beat,
        timing: None,
        extra_channels: Vec::new(),
        recording: None,
        double_stops: DoubleStops::default(),
    })
}

/// A clean étude (no augmentation, 22.05 kHz) rendered by the built-in synthesizer, with
/// the tempo drawn from `tempo_bpm`: the labelled test audio of the trackers' tests and
/// benches.
///
/// ```
/// let item = corpus::item::clean_etude(3, 8.0, (100.0, 100.0))?;
/// assert!(!item.timeline.notes.is_empty());
/// # Ok::<(), corpus::CorpusError>(())
/// ```
pub fn clean_etude(
    seed: u64,
    target_s: f64,
    tempo_bpm: (f64, f64),
) -> Result<CorpusItem, CorpusError> {
    let cfg = EtudeConfig {
        target_s,
        tempo_bpm,
        ..EtudeConfig::default()
    };
    let synth = crate::render::BowedStringSynth::default();
    make_item(seed, &cfg, &synth, RendererKind::Builtin, false)
}

/// The length in seconds of the item [`make_score_item`] makes from `score` and `seed`
/// (its performance only: no fingering, motion or audio).
pub fn performed_length_s(score: &Score, seed: u64) -> f64 {
    let root = Rng::new(seed);
    perform(score, root.fork(2).next_u64(), TEMPO_RANGE_BPM)
        .timeline
        .duration_s
}

/// The range of base tempi of repertoire performances, notated beats per minute.
pub const TEMPO_RANGE_BPM: (f64, f64) = (40.0, 200.0);

/// Makes an item from a written `score` (an étude's or a repertoire excerpt): a human
/// performance drawn from `seed` ([`perform`]) whose player hooks strokes so that most
/// bars start down-bow ([`hook_to_downbeats`]), fingering by the optimal planner, motion,
/// bow strokes, double stops ([`crate::double_stop`]), and audio from `renderer` through a
/// seeded [`Recording`] (room, stereo, noise, level, rate, lossy coding) with a tuning
/// offset of ±10 cents, or dry at 22.05 kHz when `augment` is false.
pub fn make_score_item(
    score: &Score,
    seed: u64,
    renderer: &dyn Renderer,
    kind: RendererKind,
    augment: bool,
) -> Result<CorpusItem, CorpusError> {
    let root = Rng::new(seed);
    let played = perform(score, root.fork(2).next_u64(), TEMPO_RANGE_BPM);
    let mut timeline = played.timeline;
    hook_to_downbeats(&mut timeline, &mut root.fork(HOOK_FORK));
    timeline.assign_fingering(&fingering::OptimalPlanner::default());
    let double_stops = double_stops(score, &timeline);
    let performance = performance_of(&timeline)?;
    let motion = synthesize(&performance, &SynthConfig::default())
        .map_err(|e| CorpusError::Performance(e.to_string()))?;
    let strokes = bow_strokes(&timeline);
    let mut rec_rng = root.fork(3);
    let recording = if augment {
        Recording::draw(&mut rec_rng)
    } else {
        Recording::dry(22_050)
    };
    let augmentation = Augmentation {
        tuning_cents: if augment {
            rec_rng.uniform(-10.0, 10.0)
        } else {
            0.0
        },
        ..Augmentation::none(recording.sample_rate_hz)
    };
    let settings = RenderSettings {
        sample_rate_hz: recording.sample_rate_hz,
        tuning_cents: augmentation.tuning_cents,
        seed: root.fork(4).next_u64(),
    };
    let mut dry = renderer.render(&timeline, &settings)?;
    if !double_stops.notes.is_empty() {
        let second_voice = double_stops.as_timeline(timeline.duration_s);
        let second_settings = RenderSettings {
            seed: root.fork(6).next_u64(),
            ..settings.clone()
        };
        mix_into(&mut dry, &renderer.render(&second_voice, &second_settings)?);
    }
    let tilt_db = draw_tilt_db(&mut root.fork(BOW_WEIGHT_FORK));
    apply_bow_weight(&mut dry, settings.sample_rate_hz, &strokes, tilt_db);
    let mut channels = recording
        .apply(&dry, recording.sample_rate_hz)
        .map_err(|e| CorpusError::Config(format!("recording chain: {e}")))?
        .into_iter();
    let audio = channels.next().unwrap_or_default();
    Ok(CorpusItem {
        score: score.clone(),
        timeline,
        performance,
        motion,
        audio,
        extra_channels: channels.collect(),
        recording: Some(recording),
        augmentation,
        renderer: kind,
        strokes,
        time_signature: played.time_signature,
        tempo_bpm_per_beat: played.tempo_bpm_per_beat,
        timing: Some(played.timing),
        double_stops,
    })
}
