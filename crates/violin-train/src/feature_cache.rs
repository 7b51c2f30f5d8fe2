//! The 30 fps × 128 mel dB input of a corpus item, computed once and kept beside its audio.
//!
//! Decoding, resampling and the mel transform of a 10-hour corpus take minutes; every
//! training run and evaluation of the frame-level networks needs the same spectrogram. The
//! first call for an item writes `mel30.safetensors` into the item's folder (atomically);
//! later calls read it back, as long as the audio's size and modification time still match
//! what the cache recorded. Anything else (a missing, stale, truncated or unreadable cache)
//! recomputes from the audio.

use std::path::Path;

use bowing_net::features::bowing_mel_of_file;
use bowing_net::NetError;
use candle_core::{Device, Tensor};
use ndarray::Array2;

use crate::error::Result;

/// The cache file's name inside an item folder.
pub const MEL30_CACHE: &str = "mel30.safetensors";
const FORMAT: &str = "violin-skeleton/mel30-cache";
const VERSION: u32 = 1;

fn audio_stamp(audio: &Path) -> Option<String> {
    let meta = std::fs::metadata(audio).ok()?;
    let mtime = meta
        .modified()
        .ok()?
        .duration_since(std::time::UNIX_EPOCH)
        .ok()?;
    Some(format!("{}:{}", meta.len(), mtime.as_nanos()))
}

fn read_cache(cache: &Path, stamp: &str) -> Option<Array2<f32>> {
    let file = net_core::file::read(cache).ok()?;
    file.check_format(cache, FORMAT, VERSION).ok()?;
    if file.metadata.get("audio").map(String::as_str) != Some(stamp) {
        return None;
    }
    let t = file.tensors.get("mel_db")?;
    let (frames, bands) = t.dims2().ok()?;
    let values = t.flatten_all().ok()?.to_vec1::<f32>().ok()?;
    Array2::from_shape_vec((frames, bands), values).ok()
}

/// The item's mel spectrogram ([`bowing_net::features::bowing_mel`] of `audio`), from the
/// cache in `item_dir` when it is current, otherwise computed and cached.
pub fn cached_mel30(item_dir: &Path, audio: &Path) -> Result<Array2<f32>> {
    let cache = item_dir.join(MEL30_CACHE);
    let stamp = audio_stamp(audio);
    if let Some(stamp) = &stamp {
        if let Some(mel) = read_cache(&cache, stamp) {
            return Ok(mel);
        }
    }
    let mel = bowing_mel_of_file(audio)?;
    if let Some(stamp) = stamp {
        let (frames, bands) = mel.dim();
        let values: Vec<f32> = mel.iter().copied().collect();
        let tensor = Tensor::from_vec(values, (frames, bands), &Device::Cpu)
            .map_err(|e| NetError::data(&cache, e))?;
        let meta = net_core::file::metadata(FORMAT, VERSION, &[("audio", stamp)]);
        let bytes = net_core::file::encode(&[("mel_db".to_string(), tensor)], meta)
            .map_err(|e| NetError::data(&cache, e))?;
        // A cache that cannot be written (a read-only corpus) only costs time.
        let _ = net_core::file::write_atomically(&cache, &bytes);
    }
    Ok(mel)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cache_is_written_reused_and_refreshed() {
        let dir = tempfile::tempdir().unwrap();
        let audio = dir.path().join("audio.wav");
        let spec = hound::WavSpec {
            channels: 1,
            sample_rate: 22_050,
            bits_per_sample: 16,
            sample_format: hound::SampleFormat::Int,
        };
        let write = |freq: f32| {
            let mut w = hound::WavWriter::create(&audio, spec).unwrap();
            for i in 0..22_050 {
                let s = (i as f32 * freq * std::f32::consts::TAU / 22_050.0).sin();
                w.write_sample((s * 8_000.0) as i16).unwrap();
            }
            w.finalize().unwrap();
        };
        write(440.0);
        let first = cached_mel30(dir.path(), &audio).unwrap();
        assert!(dir.path().join(MEL30_CACHE).is_file());
        assert_eq!(cached_mel30(dir.path(), &audio).unwrap(), first);
        // A corrupt cache is recomputed, not trusted.
        std::fs::write(dir.path().join(MEL30_CACHE), b"junk").unwrap();
        assert_eq!(cached_mel30(dir.path(), &audio).unwrap(), first);
        // New audio (another size/mtime) invalidates the cache.
        std::thread::sleep(std::time::Duration::from_millis(20));
        write(880.0);
        let second = cached_mel30(dir.path(), &audio).unwrap();
        assert_ne!(second, first);
    }
}
