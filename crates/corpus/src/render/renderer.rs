//! The [`Renderer`] trait every audio renderer implements, its settings and its error.

use performance::Timeline;

/// What can go wrong while rendering.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// Settings out of range.
    #[error("invalid render settings: {0}")]
    Settings(String),
    /// The SoundFont could not be read or used.
    #[error("SoundFont: {0}")]
    SoundFont(String),
}

/// Per-item rendering settings.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    /// Output sample rate in Hz.
    pub sample_rate_hz: u32,
    /// Global tuning offset in cents (labels keep their nominal MIDI pitches).
    pub tuning_cents: f64,
    /// Seed of the renderer's own random choices (vibrato, noise).
    pub seed: u64,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            sample_rate_hz: 22_050,
            tuning_cents: 0.0,
            seed: 0,
        }
    }
}

impl RenderSettings {
    /// Checks the ranges.
    pub fn validate(&self) -> Result<(), RenderError> {
        if !(8_000..=192_000).contains(&self.sample_rate_hz) {
            return Err(RenderError::Settings(format!(
                "sample rate {} Hz is outside 8000..=192000",
                self.sample_rate_hz
            )));
        }
        if !(self.tuning_cents.is_finite() && self.tuning_cents.abs() <= 100.0) {
            return Err(RenderError::Settings(format!(
                "tuning offset {} cents is outside ±100",
                self.tuning_cents
            )));
        }
        Ok(())
    }
}

/// Turns a [`Timeline`] into mono audio at `settings.sample_rate_hz`.
pub trait Renderer {
    /// Short name written in the manifest ("builtin", "soundfont").
    fn name(&self) -> &'static str;
    /// Renders the whole timeline.
    fn render(
        &self,
        timeline: &Timeline,
        settings: &RenderSettings,
    ) -> Result<Vec<f32>, RenderError>;
}
