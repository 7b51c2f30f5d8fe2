//! A trained stroke network with its decoder, as stored in a weights file.

use std::collections::HashMap;
use std::path::Path;

use candle_core::{Device, Tensor};
use candle_nn::{VarBuilder, VarMap};
use ndarray::ArrayView2;
use net_core::file::{self, TensorFile};
use net_core::nn::DropoutRng;
use net_core::vars;
use performance::{BowDirection, BowStroke};

use super::decode::{changes_inside, played_stretches, string_between};
use super::direction::{beat_places, mean_log_odds, DirectionDecoder};
use super::input::{stroke_input, tonal_prominence_db};
use super::model::{StrokeConfig, StrokeNet, DTYPE};
use super::outputs::FrameOutputs;
use crate::decode::Decoder;
use crate::error::{NetError, Result};
use crate::features::FPS;

/// Value of the `format` metadata entry of stroke-network weights.
pub const STROKE_FORMAT_NAME: &str = "violin-skeleton/bowing-stroke-net";
/// Current weights format version.
pub const STROKE_FORMAT_VERSION: u32 = 1;
/// Metadata key of the ensemble's decoder (JSON), when the file has one.
pub const KEY_ENSEMBLE_DECODER: &str = "ensemble_decoder";
/// Metadata key of the direction decoder (JSON), when the file has one.
pub const KEY_DIRECTION_DECODER: &str = "direction_decoder";

/// What the bowing model finds in a recording.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StrokeAnalysis {
    /// Bow changes, seconds.
    pub bow_changes_s: Vec<f64>,
    /// The played stretches `(start_s, end_s)` (empty from the CNN, which does not tell).
    pub played_s: Vec<(f64, f64)>,
    /// The per-frame probabilities (30 fps); `string` and `down` are empty from the CNN.
    pub frames: FrameOutputs,
    /// How directions are decoded from `frames.down` (`None`: by the bowing rules alone).
    pub direction_decoder: Option<DirectionDecoder>,
}

impl StrokeAnalysis {
    /// The string most probably bowed between two times (`None` without string output or
    /// for an empty span).
    pub fn string_between_s(&self, from_s: f64, to_s: f64) -> Option<fingering::ViolinString> {
        let frame = |t: f64| (t * FPS).round().max(0.0) as usize;
        string_between(
            &self.frames.string,
            frame(from_s),
            frame(to_s).max(frame(from_s) + 1),
        )
    }

    /// The direction of the stroke each of `bow_changes_s` starts: the bowing rules for
    /// heard strokes (`performance::heard_bow_directions` over `notes` and `downbeats_s`),
    /// or, when the weights carry a direction decoder ([`crate::stroke::direction`]), that
    /// decoder over the rules, the network's down-bow output and where each stroke starts
    /// among `beats_s` and `downbeats_s` (and, with its `long_runs`, which changes lie in
    /// long runs of `frames.change`).
    pub fn directions(
        &self,
        bow_changes_s: &[f64],
        notes: &[performance::Note],
        beats_s: &[f64],
        downbeats_s: &[f64],
    ) -> Vec<BowDirection> {
        let rules = performance::heard_bow_directions(bow_changes_s, notes, downbeats_s);
        let Some(decoder) = self.direction_decoder else {
            return rules;
        };
        let frame = |t: f64| (t * FPS).round().max(0.0) as usize;
        let evidence: Vec<f32> = performance::strokes_of(bow_changes_s, &rules, notes)
            .iter()
            .map(|s| mean_log_odds(&self.frames.down, frame(s.start_s), frame(s.end_s)))
            .collect();
        let places = beat_places(bow_changes_s, beats_s, downbeats_s);
        let flips = match decoder.long_runs {
            Some(long) => {
                let frames: Vec<usize> = bow_changes_s.iter().map(|&t| frame(t)).collect();
                long.flips(&self.frames.change, &frames, decoder.default_flip())
            }
            None => Vec::new(),
        };
        decoder.decode_with_flips(&evidence, &rules, &places, &flips)
    }

    /// Sets each stroke's string from the network where it has string output.
    pub fn assign_strings(&self, strokes: &mut [BowStroke]) {
        if self.frames.string.is_empty() {
            return;
        }
        for s in strokes {
            if let Some(string) = self.string_between_s(s.start_s, s.end_s) {
                s.string = Some(string);
            }
        }
    }
}

/// Bow changes and strings: the network, its input normalisation and its decoder.
#[derive(Debug)]
pub struct StrokeDetector {
    net: StrokeNet,
    decoder: Decoder,
    ensemble_decoder: Option<Decoder>,
    direction_decoder: Option<DirectionDecoder>,
    tensors: Vec<(String, Tensor)>,
    training: String,
}

/// The played stretches of a [`stroke_input`] (level and tonality, [`played_stretches`]).
pub fn played(input: &ndarray::Array2<f32>) -> Vec<(usize, usize)> {
    let level: Vec<f32> = input.column(input.ncols().saturating_sub(1)).to_vec();
    played_stretches(&level, &tonal_prominence_db(input))
}

/// The variable names and shapes a network of `cfg` has.
pub fn stroke_shapes(cfg: &StrokeConfig) -> Result<Vec<(String, Vec<usize>)>> {
    let varmap = VarMap::new();
    StrokeNet::new(
        cfg,
        VarBuilder::from_varmap(&varmap, DTYPE, &Device::Cpu),
        DropoutRng::new(0),
    )?;
    Ok(vars::var_shapes(&varmap))
}

impl StrokeDetector {
    /// Reads weights written by [`StrokeDetector::save`]; rejects other networks, other
    /// format versions and tensors whose shapes do not match the stored configuration.
    pub fn load(path: &Path) -> Result<Self> {
        Self::from_file(file::read(path)?, path)
    }

    /// [`StrokeDetector::load`] from bytes; `path` names them in errors.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self> {
        Self::from_file(file::decode(bytes, path)?, path)
    }

    fn from_file(file: TensorFile, path: &Path) -> Result<Self> {
        file.check_format(path, STROKE_FORMAT_NAME, STROKE_FORMAT_VERSION)?;
        let cfg: StrokeConfig = file.meta_json("config", path)?;
        cfg.validate().map_err(|e| NetError::weights(path, e))?;
        let decoder: Decoder = file.meta_json("decoder", path)?;
        let tensors = file.take_expected(path, &stroke_shapes(&cfg)?)?;
        let training = file.metadata.get("training").cloned().unwrap_or_default();
        let ensemble_decoder = match file.metadata.get(KEY_ENSEMBLE_DECODER) {
            Some(_) => Some(file.meta_json(KEY_ENSEMBLE_DECODER, path)?),
            None => None,
        };
        let direction_decoder: Option<DirectionDecoder> =
            match file.metadata.get(KEY_DIRECTION_DECODER) {
                Some(_) => Some(file.meta_json(KEY_DIRECTION_DECODER, path)?),
                None => None,
            };
        if let Some(d) = &direction_decoder {
            d.validate().map_err(|e| NetError::weights(path, e))?;
        }
        let mut d = Self::from_tensors(&cfg, tensors, decoder, training)?;
        d.ensemble_decoder = ensemble_decoder;
        d.direction_decoder = direction_decoder;
        Ok(d)
    }

    /// A detector from named tensors (as in a weights file).
    pub fn from_tensors(
        cfg: &StrokeConfig,
        tensors: Vec<(String, Tensor)>,
        decoder: Decoder,
        training: String,
    ) -> Result<Self> {
        let map: HashMap<String, Tensor> = tensors.iter().cloned().collect();
        let vb = VarBuilder::from_tensors(map, DTYPE, &Device::Cpu);
        let net = StrokeNet::new(cfg, vb, DropoutRng::new(0))?;
        Ok(Self {
            net,
            decoder,
            ensemble_decoder: None,
            direction_decoder: None,
            tensors,
            training,
        })
    }

    /// The named tensors of the network (as in its weights file).
    pub fn named_tensors(&self) -> &[(String, Tensor)] {
        &self.tensors
    }

    /// A detector holding a copy of the variables of `varmap` (e.g. during training).
    pub fn from_varmap(
        cfg: &StrokeConfig,
        varmap: &VarMap,
        decoder: Decoder,
        training: String,
    ) -> Result<Self> {
        let tensors = vars::copied_tensors(varmap)?;
        Self::from_tensors(cfg, tensors, decoder, training)
    }

    /// Writes the weights file (through a temporary file).
    pub fn save(&self, path: &Path) -> Result<()> {
        Ok(file::write_atomically(path, &self.to_bytes()?)?)
    }

    /// The weights file's bytes.
    pub fn to_bytes(&self) -> Result<Vec<u8>> {
        let mut entries = vec![
            ("config", file::to_json(self.net.config())?),
            ("decoder", file::to_json(&self.decoder)?),
            ("training", self.training.clone()),
        ];
        if let Some(d) = &self.ensemble_decoder {
            entries.push((KEY_ENSEMBLE_DECODER, file::to_json(d)?));
        }
        if let Some(d) = &self.direction_decoder {
            entries.push((KEY_DIRECTION_DECODER, file::to_json(d)?));
        }
        let meta = file::metadata(STROKE_FORMAT_NAME, STROKE_FORMAT_VERSION, &entries);
        Ok(file::encode(&self.tensors, meta)?)
    }

    /// The network.
    pub fn net(&self) -> &StrokeNet {
        &self.net
    }

    /// The bow-change decoder (chosen on validation data at training).
    pub fn decoder(&self) -> Decoder {
        self.decoder
    }

    /// Replaces the decoder.
    pub fn set_decoder(&mut self, decoder: Decoder) {
        self.decoder = decoder;
    }

    /// The decoder of the mean of this network's and the CNN's change probabilities
    /// ([`crate::BowingModel::Ensemble`]), when one was tuned on validation data.
    pub fn ensemble_decoder(&self) -> Option<Decoder> {
        self.ensemble_decoder
    }

    /// Sets the ensemble's decoder (stored with the weights).
    pub fn set_ensemble_decoder(&mut self, decoder: Option<Decoder>) {
        self.ensemble_decoder = decoder;
    }

    /// The decoder of stroke directions, when one was tuned on validation data.
    pub fn direction_decoder(&self) -> Option<DirectionDecoder> {
        self.direction_decoder
    }

    /// Sets the direction decoder (stored with the weights).
    pub fn set_direction_decoder(&mut self, decoder: Option<DirectionDecoder>) {
        self.direction_decoder = decoder;
    }

    /// How the weights were trained (JSON written by the trainer; may be empty).
    pub fn training_info(&self) -> &str {
        &self.training
    }

    /// Replaces the training description stored with the weights.
    pub fn set_training_info(&mut self, info: String) {
        self.training = info;
    }

    /// Per-frame probabilities of a `(frames, bands)` mel dB spectrogram at 30 fps.
    pub fn frame_outputs(&self, mel_db: ArrayView2<f32>) -> Result<FrameOutputs> {
        net_core::frames::check_mel(mel_db, self.net.config().n_mels)?;
        self.net.frame_outputs(&stroke_input(mel_db))
    }

    /// Bow changes, played stretches and string probabilities of a mel dB spectrogram at
    /// 30 fps.
    pub fn analyze_mel(&self, mel_db: ArrayView2<f32>) -> Result<StrokeAnalysis> {
        self.analyze_mel_with(mel_db, None)
    }

    /// [`StrokeDetector::analyze_mel`] with the change probabilities averaged with
    /// `other_change` (another model's, one per frame) and picked by the ensemble decoder
    /// (this network's own decoder when it has none).
    pub fn analyze_mel_with(
        &self,
        mel_db: ArrayView2<f32>,
        other_change: Option<&[f32]>,
    ) -> Result<StrokeAnalysis> {
        net_core::frames::check_mel(mel_db, self.net.config().n_mels)?;
        let input = stroke_input(mel_db);
        let mut frames = self.net.frame_outputs(&input)?;
        let mut decoder = self.decoder;
        if let Some(other) = other_change {
            average_changes(&mut frames.change, other);
            decoder = self.ensemble_decoder.unwrap_or(decoder);
        }
        let stretches = played(&input);
        let changes = changes_inside(&decoder.pick_fractional(&frames.change), &stretches);
        Ok(StrokeAnalysis {
            bow_changes_s: changes.iter().map(|f| f / FPS).collect(),
            played_s: stretches
                .iter()
                .map(|&(a, b)| (a as f64 / FPS, b as f64 / FPS))
                .collect(),
            frames,
            direction_decoder: self.direction_decoder,
        })
    }

    /// [`StrokeDetector::analyze_mel`] of a recording.
    pub fn analyze_audio(&self, audio: &dsp_mel::Audio) -> Result<StrokeAnalysis> {
        self.analyze_mel(crate::features::bowing_mel(audio)?.view())
    }
}

/// The ensemble's change probability: `own` (the stroke network's, per frame) becomes its
/// mean with `other` (the CNN's), as the shipped analysis combines them.
///
/// ```
/// let mut own = vec![0.2f32, 0.8];
/// bowing_net::stroke::average_changes(&mut own, &[0.6, 0.4]);
/// assert_eq!(own, vec![0.4, 0.6]);
/// ```
pub fn average_changes(own: &mut [f32], other: &[f32]) {
    for (p, o) in own.iter_mut().zip(other) {
        *p = 0.5 * (*p + o);
    }
}
