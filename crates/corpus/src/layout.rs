//! The corpus on disk. Per item, in `DIR/items/NNNNN/`:
//!
//! | file | content |
//! |---|---|
//! | `audio.wav` | 16-bit PCM at the item's sample rate, mono or stereo (`audio.mp3` or `audio.ogg` instead when the recording chain coded it lossily; see [`item_audio`]) |
//! | `performance.json` | the ground-truth `performance::Performance` |
//! | `notes.tsv` | `onset_s`, `offset_s`, `midi`, `string` (1 = G … 4 = E, 0 = none), `position`, `finger`, `dynamic` (0..1) separated by tabs, with a header |
//! | `bowchanges.txt`, `beats.txt`, `downbeats.txt` | one time in seconds per line (beats at the notated level: dotted quarters in 6/8, 9/8, 12/8; one per bar in 3/8) |
//! | `double_stops.tsv` | the second notes of double stops, played under the melody note that starts with them: same columns as `notes.tsv` (header only when there are none) |
//! | `strokes.tsv` | `start_s`, `end_s`, `direction` (`down`/`up`), `string` (1..=4, 0 = none) |
//! | `labels.json` | `time_signature`, `beats_per_bar`, `beat_quarters`, `tempo_bpm` (nominal), `tempo_bpm_per_beat` |
//! | `arousal.csv` | `time_s,arousal` at 2 Hz, in [-1, 1] |
//! | `motion.json` | ground-truth motion (skeleton's motion JSON) |
//!
//! and `DIR/manifest.json` lists the items ([`crate::manifest::Manifest`]). An item folder is
//! written under a temporary name and renamed when complete.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use skeleton::formats::MotionFormat;

use crate::error::CorpusError;
use crate::item::CorpusItem;

/// Folder of item `index` below the corpus root.
pub fn item_dir(root: &Path, index: usize) -> PathBuf {
    root.join("items").join(format!("{index:05}"))
}

fn io_err(path: &Path, e: impl std::fmt::Display) -> CorpusError {
    CorpusError::Io {
        path: path.to_path_buf(),
        reason: e.to_string(),
    }
}

fn times(values: &[f64]) -> String {
    let mut s = String::new();
    for v in values {
        let _ = writeln!(s, "{v:.6}");
    }
    s
}

/// Writes every file of `item` into `root/items/NNNNN/` (replacing an existing folder).
pub fn write_item(root: &Path, index: usize, item: &CorpusItem) -> Result<PathBuf, CorpusError> {
    let items = root.join("items");
    std::fs::create_dir_all(&items).map_err(|e| io_err(&items, e))?;
    let tmp = tempfile::Builder::new()
        .prefix(&format!(".{index:05}-"))
        .tempdir_in(&items)
        .map_err(|e| io_err(&items, e))?;
    let dir = tmp.path();
    let mut channels: Vec<&[f32]> = vec![&item.audio];
    channels.extend(item.extra_channels.iter().map(Vec::as_slice));
    let wav = dir.join("audio.wav");
    write_wav(&wav, &channels, item.augmentation.sample_rate_hz)?;
    if let Some(lossy) = item.recording.as_ref().and_then(|r| r.lossy.as_ref()) {
        let coded = dir.join(format!("audio.{}", lossy.extension()));
        crate::room::encode_lossy(&wav, lossy, &coded).map_err(|e| io_err(&coded, e))?;
        std::fs::remove_file(&wav).map_err(|e| io_err(&wav, e))?;
    }
    let perf = serde_json::to_string(&item.performance).map_err(|e| io_err(dir, e))?;
    write_text(&dir.join("performance.json"), &perf)?;
    write_text(&dir.join("notes.tsv"), &notes_tsv(&item.timeline.notes))?;
    write_text(
        &dir.join("double_stops.tsv"),
        &notes_tsv(&item.double_stops.notes),
    )?;
    let mut strokes = String::from("start_s\tend_s\tdirection\tstring\n");
    for s in &item.strokes {
        let dir = match s.direction {
            performance::BowDirection::Down => "down",
            performance::BowDirection::Up => "up",
        };
        let string = s.string.map_or(0, |x| x.number());
        let _ = writeln!(strokes, "{:.6}\t{:.6}\t{dir}\t{string}", s.start_s, s.end_s);
    }
    write_text(&dir.join("strokes.tsv"), &strokes)?;
    let labels = serde_json::json!({
        "time_signature": item.time_signature.to_string(),
        "beats_per_bar": item.time_signature.meter().beats_per_bar,
        "beat_quarters": item.time_signature.beat_quarters(),
        "tempo_bpm": item.timeline.tempo_bpm,
        "tempo_bpm_per_beat": item.tempo_bpm_per_beat,
        "work": item.score.work,
        "score": item.score.id,
    });
    write_text(&dir.join("labels.json"), &labels.to_string())?;
    write_text(
        &dir.join("bowchanges.txt"),
        &times(&item.timeline.bow_changes_s()),
    )?;
    write_text(&dir.join("beats.txt"), &times(&item.timeline.beats_s))?;
    write_text(
        &dir.join("downbeats.txt"),
        &times(&item.timeline.downbeats_s),
    )?;
    let mut arousal = String::from("time_s,arousal\n");
    for (k, a) in item.timeline.arousal_2hz.iter().enumerate() {
        let _ = writeln!(arousal, "{:.1},{a:.6}", k as f64 * 0.5);
    }
    write_text(&dir.join("arousal.csv"), &arousal)?;
    item.motion
        .write(dir.join("motion.json"), MotionFormat::Json)
        .map_err(|e| io_err(&dir.join("motion.json"), e))?;
    // tempfile creates private (0700/0600) entries; corpus files are ordinary shared files.
    atomic_file::make_ordinary(dir, true);
    let final_dir = item_dir(root, index);
    if final_dir.exists() {
        std::fs::remove_dir_all(&final_dir).map_err(|e| io_err(&final_dir, e))?;
    }
    let kept = tmp.keep();
    std::fs::rename(&kept, &final_dir).map_err(|e| io_err(&final_dir, e))?;
    Ok(final_dir)
}

/// `notes.tsv`'s text for `notes`.
fn notes_tsv(notes: &[performance::TimedNote]) -> String {
    let mut out = String::from("onset_s\toffset_s\tmidi\tstring\tposition\tfinger\tdynamic\n");
    for n in notes {
        let (string, position, finger) = n
            .note
            .fingering
            .map_or((0, 0, 0), |f| (f.string.number(), f.position, f.finger));
        let _ = writeln!(
            out,
            "{:.6}\t{:.6}\t{}\t{string}\t{position}\t{finger}\t{:.3}",
            n.note.onset_s, n.note.offset_s, n.note.midi, n.dynamic
        );
    }
    out
}

fn write_text(path: &Path, text: &str) -> Result<(), CorpusError> {
    std::fs::write(path, text).map_err(|e| io_err(path, e))
}

/// The audio file of an item folder: `audio.wav`, or `audio.mp3` / `audio.ogg` for an item
/// that was coded lossily.
pub fn item_audio(dir: &Path) -> PathBuf {
    ["audio.mp3", "audio.ogg"]
        .iter()
        .map(|f| dir.join(f))
        .find(|p| p.is_file())
        .unwrap_or_else(|| dir.join("audio.wav"))
}

fn write_wav(path: &Path, channels: &[&[f32]], rate: u32) -> Result<(), CorpusError> {
    let spec = hound::WavSpec {
        channels: channels.len().max(1) as u16,
        sample_rate: rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let file = std::fs::File::create(path).map_err(|e| io_err(path, e))?;
    let mut w =
        hound::WavWriter::new(std::io::BufWriter::new(file), spec).map_err(|e| io_err(path, e))?;
    let len = channels.iter().map(|c| c.len()).max().unwrap_or(0);
    for i in 0..len {
        for c in channels {
            let s = c.get(i).copied().unwrap_or(0.0);
            let v = (s.clamp(-1.0, 1.0) * 32767.0).round() as i16;
            w.write_sample(v).map_err(|e| io_err(path, e))?;
        }
    }
    w.finalize().map_err(|e| io_err(path, e))?;
    Ok(())
}

/// Writes `text` to `path` through a temporary file in the same folder.
pub fn write_atomic(path: &Path, text: &str) -> Result<(), CorpusError> {
    atomic_file::write_bytes_atomically(path, text.as_bytes()).map_err(|e| io_err(path, e))
}
