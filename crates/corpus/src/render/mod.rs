//! Audio renderers: the built-in bowed-string synthesizer, the digital waveguide and
//! SoundFonts (and the sample sets read into one: GUS patches, WebAudioFont instruments,
//! folders of per-note recordings), behind one [`Renderer`] trait.

mod biquad;
mod bowed;
mod gus_patch;
mod portato;
mod renderer;
mod sample_dir;
mod sf2_writer;
mod soundfont;
mod waveguide;
mod waveguide_string;
mod webaudiofont;

pub use biquad::Biquad;
pub use bowed::{BowedConfig, BowedStringSynth};
pub use gus_patch::{gus_patch_samples, sf2_from_gus_patch};
pub use portato::{is_portato, portato_gain, PORTATO_FALL_S, PORTATO_FLOOR, PORTATO_RISE_S};
pub use renderer::{RenderError, RenderSettings, Renderer};
pub use sample_dir::{note_key, sample_dir_samples, MAX_SAMPLE_S};
pub use sf2_writer::{tiny_violin_sf2, write_sf2, Sf2Sample};
pub use soundfont::SoundFontRenderer;
pub use waveguide::{WaveguideConfig, WaveguideViolin};
pub use webaudiofont::webaudiofont_samples;
