//! Reading an audio file a piece at a time, so long recordings never have to sit in memory
//! whole.

use std::fs::File;
use std::path::{Path, PathBuf};

use symphonia::core::codecs::audio::{AudioDecoder, AudioDecoderOptions};
use symphonia::core::errors::Error as SymError;
use symphonia::core::formats::probe::Hint;
use symphonia::core::formats::{FormatOptions, FormatReader, TrackType};
use symphonia::core::io::MediaSourceStream;
use symphonia::core::meta::MetadataOptions;

use crate::error::{DspError, Result};

/// The lowest sample rate a file may declare, Hz.
pub const MIN_FILE_RATE_HZ: u32 = 4_000;
/// The highest sample rate a file may declare, Hz.
pub const MAX_FILE_RATE_HZ: u32 = 768_000;

/// How many undecodable packets in a row we skip before calling the file corrupt.
const MAX_CONSECUTIVE_BAD_PACKETS: usize = 16;

/// A decoder that hands out a file's audio as mono `f32` in pieces of any size, at the file's
/// own sample rate. [`crate::load_audio`] is this reader read to the end.
///
/// The same file checks apply as for `load_audio`: a missing file, a directory, an empty file,
/// an unsupported or corrupt file, and a NaN sample are errors; a file cut short ends early
/// and keeps what could be decoded.
///
/// ```no_run
/// let mut reader = dsp_mel::AudioReader::open("long_take.flac")?;
/// let mut piece = Vec::new();
/// let mut total = 0;
/// while reader.read_mono(44_100 * 60, &mut piece)? > 0 {
///     total += piece.len();        // one minute (or the rest) at a time
///     piece.clear();
/// }
/// println!("{total} samples at {} Hz", reader.sample_rate_hz());
/// # Ok::<(), dsp_mel::DspError>(())
/// ```
pub struct AudioReader {
    path: PathBuf,
    format: Box<dyn FormatReader>,
    decoder: Box<dyn AudioDecoder>,
    track_id: u32,
    sample_rate_hz: u32,
    total_frames: Option<u64>,
    /// Decoded mono samples not yet handed out.
    pending: Vec<f32>,
    interleaved: Vec<f32>,
    /// Mono samples handed out so far.
    delivered: usize,
    finished: bool,
}

impl std::fmt::Debug for AudioReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AudioReader")
            .field("path", &self.path)
            .field("sample_rate_hz", &self.sample_rate_hz)
            .field("total_frames", &self.total_frames)
            .field("delivered", &self.delivered)
            .finish_non_exhaustive()
    }
}

impl AudioReader {
    /// Opens and probes `path` (WAV, FLAC, MP3, OGG/Vorbis; any rate and channel count).
    pub fn open(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => DspError::NotFound { path: path.into() },
            _ => DspError::Io {
                path: path.into(),
                source: e,
            },
        })?;
        if meta.is_dir() {
            return Err(DspError::IsDirectory { path: path.into() });
        }
        if meta.len() == 0 {
            return Err(DspError::EmptyFile { path: path.into() });
        }
        let file = File::open(path).map_err(|e| DspError::Io {
            path: path.into(),
            source: e,
        })?;
        let extension = path.extension().and_then(|e| e.to_str());
        Self::from_source(path, Box::new(file), extension)
    }

    /// A reader of audio held in memory (an MP3 inside a container, say); `label` names it
    /// in errors as a path would, `extension` (`"mp3"`, `"wav"`, …) helps the format probe.
    /// Empty bytes are [`DspError::EmptyFile`].
    ///
    /// ```
    /// let err = dsp_mel::AudioReader::from_bytes(Vec::new(), "zone 1".as_ref(), Some("mp3"));
    /// assert!(matches!(err, Err(dsp_mel::DspError::EmptyFile { .. })));
    /// ```
    pub fn from_bytes(bytes: Vec<u8>, label: &Path, extension: Option<&str>) -> Result<Self> {
        if bytes.is_empty() {
            return Err(DspError::EmptyFile { path: label.into() });
        }
        Self::from_source(label, Box::new(std::io::Cursor::new(bytes)), extension)
    }

    /// Probes `source` and opens its first audio track (shared by [`Self::open`] and
    /// [`Self::from_bytes`]).
    fn from_source(
        path: &Path,
        source: Box<dyn symphonia::core::io::MediaSource>,
        extension: Option<&str>,
    ) -> Result<Self> {
        let unsupported = |reason: String| DspError::Unsupported {
            path: path.into(),
            reason,
        };
        let mss = MediaSourceStream::new(source, Default::default());
        let mut hint = Hint::new();
        if let Some(ext) = extension {
            hint.with_extension(ext);
        }
        // Codec libraries can panic on a damaged stream: that is a corrupt file, not a crash.
        let (format, decoder, track_id, total_frames, sample_rate_hz) =
            crate::guard::guarded(path, || {
                let format = symphonia::default::get_probe()
                    .probe(
                        &hint,
                        mss,
                        FormatOptions::default(),
                        MetadataOptions::default(),
                    )
                    .map_err(|e| unsupported(e.to_string()))?;
                let track = format
                    .default_track(TrackType::Audio)
                    .ok_or_else(|| unsupported("no audio track".into()))?;
                let track_id = track.id;
                let total_frames = track.num_frames;
                let params = track
                    .codec_params
                    .as_ref()
                    .and_then(|p| p.audio())
                    .ok_or_else(|| unsupported("no audio codec parameters".into()))?;
                let sample_rate_hz = params.sample_rate.unwrap_or(0);
                let decoder = symphonia::default::get_codecs()
                    .make_audio_decoder(params, &AudioDecoderOptions::default())
                    .map_err(|e| unsupported(e.to_string()))?;
                Ok((format, decoder, track_id, total_frames, sample_rate_hz))
            })?;
        let mut reader = Self {
            path: path.into(),
            format,
            decoder,
            track_id,
            sample_rate_hz,
            total_frames,
            pending: Vec::new(),
            interleaved: Vec::new(),
            delivered: 0,
            finished: false,
        };
        // Decode the first packet now, so a file that has no audio fails at open and a
        // stream without a rate in its header learns it from the first buffer.
        reader.decode_next()?;
        if reader.pending.is_empty() && reader.finished {
            return Err(DspError::NoSamples { path: path.into() });
        }
        if reader.sample_rate_hz == 0 {
            return Err(DspError::Corrupt {
                path: path.into(),
                reason: "sample rate is 0".into(),
            });
        }
        // A header that says 1 Hz makes a 60 kB file last nine hours, and resampling it to
        // the analysis rate would take minutes and gigabytes (found by input-fuzz).
        if !(MIN_FILE_RATE_HZ..=MAX_FILE_RATE_HZ).contains(&reader.sample_rate_hz) {
            return Err(DspError::Corrupt {
                path: path.into(),
                reason: format!(
                    "its header gives a sample rate of {} Hz, outside the {} Hz – {} kHz of audio recordings; the file is damaged or not audio",
                    reader.sample_rate_hz,
                    MIN_FILE_RATE_HZ,
                    MAX_FILE_RATE_HZ / 1000
                ),
            });
        }
        Ok(reader)
    }

    /// The file's sample rate in Hz.
    pub fn sample_rate_hz(&self) -> u32 {
        self.sample_rate_hz
    }

    /// The number of mono samples the container announces, when it does (WAV and FLAC
    /// usually do; a truncated file delivers fewer).
    pub fn total_samples_hint(&self) -> Option<u64> {
        self.total_frames
    }

    /// Mono samples handed out so far.
    pub fn samples_read(&self) -> usize {
        self.delivered
    }

    /// Appends up to `max_samples` mono samples to `out` and returns how many were appended;
    /// 0 means the end of the file.
    pub fn read_mono(&mut self, max_samples: usize, out: &mut Vec<f32>) -> Result<usize> {
        let start = out.len();
        // Packets are moved to `out` one at a time, so only one packet's worth of samples
        // ever waits in `pending`.
        loop {
            let need = max_samples - (out.len() - start);
            let n = need.min(self.pending.len());
            out.extend(self.pending.drain(..n));
            if out.len() - start == max_samples || self.finished {
                break;
            }
            self.decode_next()?;
        }
        if let Some(i) = crate::stft::first_non_finite(&out[start..]) {
            return Err(DspError::NonFinite {
                source_name: self.path.display().to_string(),
                index: self.delivered + i,
            });
        }
        let n = out.len() - start;
        self.delivered += n;
        Ok(n)
    }

    /// [`Self::decode_packets`] under the panic guard; after a caught panic the stream ends.
    fn decode_next(&mut self) -> Result<()> {
        let path = self.path.clone();
        let r = crate::guard::guarded(&path, || self.decode_packets());
        if r.is_err() {
            self.finished = true;
        }
        r
    }

    /// Decodes packets until one adds samples to `pending` or the stream ends.
    fn decode_packets(&mut self) -> Result<()> {
        let mut bad_in_a_row = 0usize;
        let mut last_decode_error = String::new();
        let corrupt = |path: &Path, reason: String| DspError::Corrupt {
            path: path.into(),
            reason,
        };
        let nothing_yet = self.delivered == 0 && self.pending.is_empty();
        loop {
            let packet = match self.format.next_packet() {
                Ok(Some(p)) => p,
                // A file cut short ends the stream: keep what was decoded.
                Ok(None) | Err(SymError::IoError(_)) | Err(SymError::ResetRequired) => {
                    self.finished = true;
                    break;
                }
                Err(e) => {
                    if nothing_yet {
                        return Err(corrupt(&self.path, e.to_string()));
                    }
                    self.finished = true;
                    break;
                }
            };
            if packet.track_id != self.track_id {
                continue;
            }
            match self.decoder.decode(&packet) {
                Ok(buf) => {
                    let channels = buf.spec().channels().count().max(1);
                    if self.sample_rate_hz == 0 {
                        self.sample_rate_hz = buf.spec().rate();
                    }
                    buf.copy_to_vec_interleaved(&mut self.interleaved);
                    let before = self.pending.len();
                    mix_down_into(&self.interleaved, channels, &mut self.pending);
                    if self.pending.len() > before {
                        return Ok(());
                    }
                    bad_in_a_row = 0;
                }
                Err(SymError::DecodeError(e)) => {
                    last_decode_error = e.to_string();
                    bad_in_a_row += 1;
                }
                Err(SymError::IoError(e)) => {
                    last_decode_error = e.to_string();
                    bad_in_a_row += 1;
                }
                Err(e) => return Err(corrupt(&self.path, e.to_string())),
            }
            if bad_in_a_row > MAX_CONSECUTIVE_BAD_PACKETS {
                return Err(corrupt(&self.path, last_decode_error));
            }
        }
        if nothing_yet && !last_decode_error.is_empty() {
            return Err(corrupt(&self.path, last_decode_error));
        }
        Ok(())
    }
}

/// Averages interleaved channels into `out` (appending).
pub(crate) fn mix_down_into(interleaved: &[f32], channels: usize, out: &mut Vec<f32>) {
    if channels == 1 {
        out.extend_from_slice(interleaved);
        return;
    }
    let scale = 1.0 / channels as f32;
    out.extend(
        interleaved
            .chunks_exact(channels)
            .map(|frame| frame.iter().sum::<f32>() * scale),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mixdown_averages_channels() {
        let mut out = Vec::new();
        mix_down_into(&[1.0, 3.0, -1.0, 1.0], 2, &mut out);
        assert_eq!(out, vec![2.0, 0.0]);
    }
}
