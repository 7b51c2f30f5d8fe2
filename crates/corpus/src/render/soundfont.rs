//! The SoundFont renderer: GM program 40 (violin) of any SF2 file through rustysynth.
//!
//! Slurred notes stay under one held key: the synthesizer's pitch bend (range ±12 semitones,
//! set by RPN 0) glides to the next pitch, so no new attack is heard. A slur interval beyond
//! an octave starts the new key before releasing the old one (legato overlap). Every bow
//! change releases the key and strikes a new one (a re-attack). Vibrato is pitch bend too.
//! A slurred note on the same pitch is played portato: the expression controller (CC 11)
//! dips and swells around its onset ([`portato_gain`]).

use std::path::Path;
use std::sync::Arc;

use rustysynth::{SoundFont, Synthesizer, SynthesizerSettings};

use crate::render::portato::portato_gain;
use crate::render::renderer::{RenderError, RenderSettings, Renderer};
use net_core::rng::Rng;
use performance::{TimedNote, Timeline};

/// Samples rendered between control updates (pitch bend, events).
const BLOCK: usize = 64;
/// Pitch-bend range set through RPN 0, in semitones.
const BEND_RANGE: f64 = 12.0;

/// Renders with a SoundFont.
#[derive(Clone)]
pub struct SoundFontRenderer {
    font: Arc<SoundFont>,
    program: u8,
}

impl std::fmt::Debug for SoundFontRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SoundFontRenderer")
            .field("program", &self.program)
            .finish_non_exhaustive()
    }
}

impl SoundFontRenderer {
    /// Reads an SF2 file (SF3/Ogg-compressed fonts are not supported by rustysynth).
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self, RenderError> {
        Self::from_file_with(path.as_ref(), Self::from_bytes)
    }

    /// Reads the file at `path` and makes a renderer of its bytes with `parse`; errors name
    /// the file.
    pub(crate) fn from_file_with(
        path: &Path,
        parse: impl FnOnce(&[u8]) -> Result<Self, RenderError>,
    ) -> Result<Self, RenderError> {
        let bytes = std::fs::read(path).map_err(|e| {
            RenderError::SoundFont(format!("{}: cannot read ({e})", path.display()))
        })?;
        parse(&bytes).map_err(|e| RenderError::SoundFont(format!("{}: {e}", path.display())))
    }

    /// Parses SF2 bytes.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, RenderError> {
        let font = SoundFont::new(&mut &bytes[..])
            .map_err(|e| RenderError::SoundFont(format!("not a usable SF2 SoundFont ({e:?})")))?;
        Ok(Self {
            font: Arc::new(font),
            program: 40,
        })
    }

    /// The same font playing GM program `program` (0-based: 40 violin, 48 string ensemble,
    /// 110 fiddle).
    pub fn with_program(&self, program: u8) -> Self {
        Self {
            font: Arc::clone(&self.font),
            program: program.min(127),
        }
    }

    /// Whether the font has a preset for GM program `program` in bank 0.
    pub fn has_program(&self, program: u8) -> bool {
        self.font
            .get_presets()
            .iter()
            .any(|p| p.get_bank_number() == 0 && p.get_patch_number() == i32::from(program))
    }
}

struct Synth {
    inner: Synthesizer,
}

impl Synth {
    fn cc(&mut self, controller: i32, value: i32) {
        self.inner.process_midi_message(0, 0xB0, controller, value);
    }

    fn bend(&mut self, semitones: f64) {
        let v = (8192.0 + semitones / BEND_RANGE * 8192.0)
            .round()
            .clamp(0.0, 16383.0) as i32;
        self.inner.process_midi_message(0, 0xE0, v & 0x7F, v >> 7);
    }
}

/// Expression (CC 11) of a note's dynamic.
fn expression_of(n: &TimedNote) -> i32 {
    (40.0 + 87.0 * f64::from(n.dynamic)) as i32
}

fn velocity(n: &TimedNote) -> i32 {
    let v = 35.0 + 85.0 * f64::from(n.dynamic) + if n.accent { 10.0 } else { 0.0 };
    v.clamp(1.0, 127.0) as i32
}

impl Renderer for SoundFontRenderer {
    fn name(&self) -> &'static str {
        "soundfont"
    }

    fn render(
        &self,
        timeline: &Timeline,
        settings: &RenderSettings,
    ) -> Result<Vec<f32>, RenderError> {
        settings.validate()?;
        let sr = settings.sample_rate_hz;
        let mut synth_settings = SynthesizerSettings::new(sr as i32);
        synth_settings.enable_reverb_and_chorus = false;
        let inner = Synthesizer::new(&self.font, &synth_settings)
            .map_err(|e| RenderError::SoundFont(format!("synthesizer: {e:?}")))?;
        let mut synth = Synth { inner };
        synth
            .inner
            .process_midi_message(0, 0xC0, i32::from(self.program), 0);
        for (c, v) in [(101, 0), (100, 0), (6, BEND_RANGE as i32), (38, 0)] {
            synth.cc(c, v);
        }
        let mut rng = Rng::new(settings.seed);
        let vib: Vec<(f64, f64, f64)> = timeline
            .notes
            .iter()
            .map(|n| {
                let open = n.note.fingering.is_some_and(|f| f.is_open());
                let depth = if open || n.note.offset_s - n.note.onset_s < 0.25 {
                    0.0
                } else {
                    rng.uniform(10.0, 25.0)
                };
                (depth, rng.uniform(5.0, 7.0), rng.uniform(0.12, 0.3))
            })
            .collect();
        // Per-note intonation (±4 cents) and bow-weight (velocity ±6) variation.
        let mut var_rng = rng.fork(7);
        let detune: Vec<f64> = (0..timeline.notes.len())
            .map(|_| var_rng.uniform(-0.04, 0.04))
            .collect();
        let vel_jitter: Vec<i32> = (0..timeline.notes.len())
            .map(|_| var_rng.int(-6, 6) as i32)
            .collect();
        let tune = settings.tuning_cents / 100.0;
        let n_samples = (timeline.duration_s * f64::from(sr)).ceil() as usize;
        let mut out = Vec::with_capacity(n_samples);
        let (mut left, mut right) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
        // CC 11 of the latest note, and the value last sent (they differ during a portato).
        let (mut expression, mut sent_expression) = (0i32, -1i32);
        let mut next = 0usize; // next note to start
        let mut held: Option<(i32, usize)> = None; // (key, note index)
        let notes = &timeline.notes;
        let mut pos = 0usize;
        while pos < n_samples {
            let t = pos as f64 / f64::from(sr);
            // Note ends.
            if let Some((key, idx)) = held {
                let ends_stroke = notes.get(idx + 1).is_none_or(|m| m.bow_change);
                if ends_stroke && t >= notes[idx].note.offset_s {
                    synth.inner.note_off(0, key);
                    held = None;
                }
            }
            // Note starts.
            while next < notes.len() && notes[next].note.onset_s <= t {
                let n = &notes[next];
                let key = i32::from(n.note.midi);
                match held {
                    Some((old_key, _))
                        if !n.bow_change && (key - old_key).abs() <= BEND_RANGE as i32 =>
                    {
                        held = Some((old_key, next));
                    }
                    Some((old_key, _)) => {
                        synth
                            .inner
                            .note_on(0, key, (velocity(n) + vel_jitter[next]).clamp(1, 127));
                        synth.inner.note_off(0, old_key);
                        held = Some((key, next));
                    }
                    None => {
                        synth
                            .inner
                            .note_on(0, key, (velocity(n) + vel_jitter[next]).clamp(1, 127));
                        held = Some((key, next));
                    }
                }
                expression = expression_of(n);
                synth.cc(11, expression);
                sent_expression = expression;
                next += 1;
            }
            // Portato: the expression dips around a repeated pitch under one bow.
            if let Some((_, idx)) = held {
                let gain = portato_gain(notes, idx, t);
                // The synthesizer's channel gain is the square of the expression (GM).
                let value = if gain < 1.0 {
                    (f64::from(expression) * gain.sqrt()).round() as i32
                } else {
                    expression
                };
                if value != sent_expression {
                    synth.cc(11, value);
                    sent_expression = value;
                }
            }
            // Pitch: slur glide towards the sounding note, vibrato, tuning.
            if let Some((key, idx)) = held {
                let n = &notes[idx];
                let mut target = f64::from(n.note.midi);
                let since = t - n.note.onset_s;
                if idx > 0 && !n.bow_change && since < 0.025 {
                    let x = since / 0.025;
                    let s = x * x * (3.0 - 2.0 * x);
                    target = f64::from(notes[idx - 1].note.midi) * (1.0 - s) + target * s;
                }
                let (depth, rate, delay) = vib[idx];
                if depth > 0.0 && since > delay {
                    let ramp = ((since - delay) / 0.2).min(1.0);
                    target += ramp * depth / 100.0
                        * (std::f64::consts::TAU * rate * (since - delay)).sin();
                }
                synth.bend(target - f64::from(key) + tune + detune[idx]);
            }
            let len = BLOCK.min(n_samples - pos);
            synth.inner.render(&mut left[..len], &mut right[..len]);
            out.extend(
                left[..len]
                    .iter()
                    .zip(&right[..len])
                    .map(|(l, r)| 0.5 * (l + r)),
            );
            pos += len;
        }
        Ok(out)
    }
}
