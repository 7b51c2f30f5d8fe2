//! One corpus item: an étude, its timeline, its ground-truth `Performance`, audio and motion.

use motion_synth::{synthesize, SynthConfig};
use performance::Performance;
use serde::{Deserialize, Serialize};
use skeleton::Motion;

use crate::augment::Augmentation;
use crate::error::CorpusError;
use crate::etude::{generate, EtudeConfig};
use crate::render::{RenderSettings, Renderer};
use crate::score::Etude;
use crate::timing::play;
use net_core::rng::Rng;
use performance::Timeline;

/// Which renderer made an item.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RendererKind {
    /// The built-in bowed-string synthesizer.
    Builtin,
    /// A SoundFont through rustysynth.
    Soundfont,
}

/// Everything made for one item, in memory.
#[derive(Debug, Clone)]
pub struct CorpusItem {
    /// The written étude.
    pub etude: Etude,
    /// The étude as played (seconds, labels).
    pub timeline: Timeline,
    /// The ground-truth performance (motion-synth's input).
    pub performance: Performance,
    /// Ground-truth motion synthesised from the performance.
    pub motion: Motion,
    /// Mono audio at `augmentation.sample_rate_hz`.
    pub audio: Vec<f32>,
    /// How the audio was augmented.
    pub augmentation: Augmentation,
    /// Which renderer made the audio.
    pub renderer: RendererKind,
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
    augmentation.apply(&mut audio, root.fork(5).next_u64());
    Ok(CorpusItem {
        etude,
        timeline,
        performance,
        motion,
        audio,
        augmentation,
        renderer: kind,
    })
}
