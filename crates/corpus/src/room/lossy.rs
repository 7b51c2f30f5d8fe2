//! Lossy re-encoding of a written item by the `lame` (MP3) and `oggenc` (Ogg Vorbis)
//! command-line encoders, with options that make the output bytes a function of the input
//! and the drawn settings only.

use std::path::Path;
use std::process::Command;

use serde::{Deserialize, Serialize};

use crate::room::error::RoomError;

/// The lossy codec.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LossyKind {
    /// MPEG-1/2 Layer III by `lame`, constant bit rate.
    Mp3,
    /// Ogg Vorbis by `oggenc`, variable bit rate at a quality level.
    Vorbis,
}

/// A drawn lossy encoding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct LossyEncoding {
    /// The codec.
    pub kind: LossyKind,
    /// Bit rate in kbit/s for MP3 (64–192), quality level for Vorbis (0–6).
    pub quality: u32,
    /// Ogg stream serial number (Ogg otherwise picks a random one; unused for MP3).
    pub serial: u32,
}

impl LossyEncoding {
    /// File extension of the encoded file (`"mp3"` or `"ogg"`).
    pub fn extension(&self) -> &'static str {
        match self.kind {
            LossyKind::Mp3 => "mp3",
            LossyKind::Vorbis => "ogg",
        }
    }

    /// The encoder program and its arguments for `wav_path` → `out_path`.
    ///
    /// * `lame --quiet --noreplaygain -b N --resample R`: constant bit rate at the input's
    ///   own rate `R` kHz (lame would otherwise drop the rate at low bit rates, moving the
    ///   file away from its labels' rate); no ID3 tag is written (none is asked for), and the
    ///   LAME header holds only the encoder version and settings;
    /// * `oggenc -Q -q Q --serial S`: the serial fixed, the only random field of an Ogg file.
    pub fn command(
        &self,
        wav_path: &Path,
        out_path: &Path,
        sample_rate_hz: u32,
    ) -> (&'static str, Vec<String>) {
        let wav = wav_path.display().to_string();
        let out = out_path.display().to_string();
        match self.kind {
            LossyKind::Mp3 => (
                "lame",
                vec![
                    "--quiet".into(),
                    "--noreplaygain".into(),
                    "-b".into(),
                    self.quality.to_string(),
                    "--resample".into(),
                    format!("{}", f64::from(sample_rate_hz) / 1000.0),
                    wav,
                    out,
                ],
            ),
            LossyKind::Vorbis => (
                "oggenc",
                vec![
                    "-Q".into(),
                    "-q".into(),
                    self.quality.to_string(),
                    "--serial".into(),
                    self.serial.to_string(),
                    "-o".into(),
                    out,
                    wav,
                ],
            ),
        }
    }
}

/// The error for an encoder that could not be started: missing, or another reason.
fn start_error(tool: &'static str, e: &std::io::Error) -> RoomError {
    if e.kind() == std::io::ErrorKind::NotFound {
        RoomError::EncoderMissing { tool }
    } else {
        RoomError::Encoder {
            tool,
            reason: e.to_string(),
        }
    }
}

/// Checks that both encoders run (`lame --version`, `oggenc --version`), so that a corpus
/// build that may draw lossy recordings fails before it renders anything rather than at its
/// first lossy item.
pub fn check_encoders() -> Result<(), RoomError> {
    for tool in ["lame", "oggenc"] {
        Command::new(tool)
            .arg("--version")
            .output()
            .map_err(|e| start_error(tool, &e))?;
    }
    Ok(())
}

/// Encodes the WAV file `wav_path` (16-bit PCM is accepted by both encoders) to `out_path`
/// with `encoding`. The same input and encoding give identical bytes.
///
/// Fails with [`RoomError::EncoderMissing`] naming the program when `lame` or `oggenc` is not
/// installed, and with [`RoomError::Encoder`] (its exit status and message) when it fails.
pub fn encode_lossy(
    wav_path: &Path,
    encoding: &LossyEncoding,
    out_path: &Path,
) -> Result<(), RoomError> {
    let sample_rate_hz = hound::WavReader::open(wav_path)
        .map(|r| r.spec().sample_rate)
        .map_err(|e| RoomError::Encoder {
            tool: encoding.command(wav_path, out_path, 0).0,
            reason: format!("cannot read {}: {e}", wav_path.display()),
        })?;
    let (tool, args) = encoding.command(wav_path, out_path, sample_rate_hz);
    let output = Command::new(tool)
        .args(&args)
        .output()
        .map_err(|e| start_error(tool, &e))?;
    if !output.status.success() {
        return Err(RoomError::Encoder {
            tool,
            reason: format!(
                "{} encoding {}: {}",
                output.status,
                wav_path.display(),
                String::from_utf8_lossy(&output.stderr).trim()
            ),
        });
    }
    Ok(())
}

/// True when `tool` can be started (used by tests to tell a missing encoder apart).
#[cfg(test)]
fn tool_available(tool: &str) -> bool {
    Command::new(tool)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success() || !o.stdout.is_empty() || !o.stderr.is_empty())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]
    use super::*;

    fn write_wav(path: &Path, sr: u32) {
        let spec = hound::WavSpec {
            channels: 2,
            sample_rate: sr,
            bits_per_sample: 16,
            sample_format: hound::SampleFormat::Int,
        };
        let mut w = hound::WavWriter::create(path, spec).unwrap();
        for i in 0..sr {
            let t = f64::from(i) / f64::from(sr);
            let env = (std::f64::consts::PI * t).sin();
            let l = 0.4 * env * (std::f64::consts::TAU * 440.0 * t).sin();
            let r = 0.3 * env * (std::f64::consts::TAU * 660.0 * t).sin();
            w.write_sample((l * 32_767.0) as i16).unwrap();
            w.write_sample((r * 32_767.0) as i16).unwrap();
        }
        w.finalize().unwrap();
    }

    #[test]
    fn encoding_twice_gives_identical_bytes_that_dsp_mel_decodes() {
        let dir = tempfile::tempdir().unwrap();
        let wav = dir.path().join("in.wav");
        write_wav(&wav, 44_100);
        for enc in [
            LossyEncoding {
                kind: LossyKind::Mp3,
                quality: 96,
                serial: 0,
            },
            LossyEncoding {
                kind: LossyKind::Vorbis,
                quality: 2,
                serial: 123_456,
            },
        ] {
            let tool = enc.command(&wav, &wav, 44_100).0;
            if !tool_available(tool) {
                println!("SKIPPED: {tool} is not installed on this machine");
                continue;
            }
            let a = dir.path().join(format!("a.{}", enc.extension()));
            let b = dir.path().join(format!("b.{}", enc.extension()));
            encode_lossy(&wav, &enc, &a).unwrap();
            encode_lossy(&wav, &enc, &b).unwrap();
            let (ba, bb) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
            assert!(!ba.is_empty());
            assert_eq!(ba, bb, "{tool} output differs between runs");
            let audio = dsp_mel::load_audio(&a).unwrap();
            assert_eq!(audio.sample_rate_hz(), 44_100);
            let secs = audio.duration_s();
            assert!((secs - 1.0).abs() < 0.1, "{tool}: decoded {secs} s");
            let peak = audio.peak();
            assert!((0.2..0.6).contains(&peak), "{tool}: decoded peak {peak}");
        }
    }

    #[test]
    fn the_encoder_check_agrees_with_the_tools() {
        let both = tool_available("lame") && tool_available("oggenc");
        match check_encoders() {
            Ok(()) => assert!(both, "the check passed without both encoders"),
            Err(e) => {
                assert!(!both, "the check failed with both encoders present: {e}");
                let msg = e.to_string();
                assert!(msg.contains("apt-get install lame vorbis-tools"), "{msg}");
            }
        }
        let msg = RoomError::EncoderMissing { tool: "oggenc" }.to_string();
        assert!(
            msg.contains("`oggenc`") && msg.contains("vorbis-tools"),
            "{msg}"
        );
        assert!(msg.contains("--no-augment"), "{msg}");
    }

    #[test]
    fn a_missing_encoder_is_named() {
        let enc = LossyEncoding {
            kind: LossyKind::Mp3,
            quality: 128,
            serial: 0,
        };
        let dir = tempfile::tempdir().unwrap();
        // A bad input file: the encoder (when present) fails and says so.
        let missing = dir.path().join("missing.wav");
        let err = encode_lossy(&missing, &enc, &dir.path().join("x.mp3")).unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("lame"), "{msg}");
    }
}
