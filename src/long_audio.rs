//! Recordings of any length with bounded memory: the file is decoded a piece at a time and
//! analysed in overlapping chunks whose results are stitched together.
//!
//! A chunk is `core` seconds that it owns plus a `margin` of context on each side that it
//! analyses but does not keep (notes, beats and bow changes near a chunk's edge are seen
//! with their surroundings). Files up to 1.5 × `core` long are one chunk: the whole file,
//! exactly as [`Pipeline::analyze`] does it.

use std::path::Path;
use std::time::Instant;

use dsp_mel::{Audio, AudioReader};
use skeleton::Motion;

use crate::chunking::{check_length, Chunking};
use crate::error::{Error, Result};
use crate::pipeline::{Method, Pipeline, StageTimings};
use performance::{Analysis, ArousalCurve, BowStroke, F0Track, Note};

/// One piece of the recording: its audio (core plus margins) and where it sits.
struct Chunk {
    audio: Audio,
    /// Start of the window (core minus the left margin), seconds from the file's start.
    window_start_s: f64,
    core_start_s: f64,
    core_end_s: f64,
}

/// Reads `reader` and calls `each` on consecutive overlapping chunks; returns the file's
/// duration and the time spent decoding, in seconds. Keeps at most about
/// `margin + 1.5 core + margin` seconds of audio.
fn for_each_chunk(
    reader: &mut AudioReader,
    chunking: Chunking,
    mut each: impl FnMut(Chunk) -> Result<()>,
) -> Result<(f64, f64)> {
    let mut decode_s = 0.0;
    let rate = reader.sample_rate_hz();
    let rate_f = f64::from(rate);
    let core = ((chunking.core_s.max(1.0)) * rate_f) as usize;
    let margin = ((chunking.margin_s.max(0.0)) * rate_f) as usize;
    let mut buf: Vec<f32> = Vec::new();
    let mut buf_start = 0usize; // absolute index of buf[0]
    let mut core_start = 0usize;
    let mut at_end = false;
    loop {
        let want_end = core_start + core + margin + core / 2;
        let clock = Instant::now();
        while !at_end && buf_start + buf.len() < want_end {
            let need = want_end - (buf_start + buf.len());
            if reader.read_mono(need, &mut buf)? == 0 {
                at_end = true;
            }
        }
        decode_s += clock.elapsed().as_secs_f64();
        let end = buf_start + buf.len();
        let last = at_end && end <= core_start + core + core / 2;
        let core_end = if last { end } else { core_start + core };
        let window_start = core_start.saturating_sub(margin).max(buf_start);
        let window_end = if last { end } else { core_end + margin };
        let samples = if last && window_start == buf_start {
            std::mem::take(&mut buf) // the whole rest: hand it over, no copy
        } else {
            buf[window_start - buf_start..window_end - buf_start].to_vec()
        };
        each(Chunk {
            audio: Audio::new(samples, rate)?,
            window_start_s: window_start as f64 / rate_f,
            core_start_s: core_start as f64 / rate_f,
            core_end_s: core_end as f64 / rate_f,
        })?;
        if last {
            return Ok((end as f64 / rate_f, decode_s));
        }
        core_start = core_end;
        let keep_from = core_start.saturating_sub(margin);
        buf.drain(..keep_from - buf_start);
        buf_start = keep_from;
    }
}

/// Appends the values of a regular series (`values[i]` at `i · step_s` in the window) that
/// fall in the chunk's core to `out` (indexed on the file's own grid of the same step).
fn take_series<T: Copy>(values: &[T], step_s: f64, chunk: &Chunk, out: &mut Vec<T>) {
    if values.is_empty() || step_s <= 0.0 {
        return;
    }
    let first = out.len();
    let last = (chunk.core_end_s / step_s).ceil() as usize;
    for j in first..last {
        let i = ((j as f64 * step_s - chunk.window_start_s) / step_s).round();
        let i = (i.max(0.0) as usize).min(values.len() - 1);
        out.push(values[i]);
    }
}

/// Events (seconds in the window) that fall in the chunk's core, in file time.
fn take_events(events_s: &[f64], chunk: &Chunk, out: &mut Vec<f64>) {
    out.extend(
        events_s
            .iter()
            .map(|t| t + chunk.window_start_s)
            .filter(|t| *t >= chunk.core_start_s && *t < chunk.core_end_s),
    );
}

/// Drops events closer than `fraction` of the median spacing to the one before (a beat seen
/// by both chunks on either side of a seam).
fn drop_crowded(events_s: &mut Vec<f64>, fraction: f64) {
    if events_s.len() < 3 {
        return;
    }
    let mut gaps: Vec<f64> = events_s.windows(2).map(|w| w[1] - w[0]).collect();
    gaps.sort_by(f64::total_cmp);
    let min_gap = gaps[gaps.len() / 2] * fraction;
    let mut kept: Vec<f64> = Vec::with_capacity(events_s.len());
    for &t in events_s.iter() {
        match kept.last() {
            Some(&prev) if t - prev < min_gap => {}
            _ => kept.push(t),
        }
    }
    *events_s = kept;
}

/// Notes of a chunk whose onset is in its core, in file time; a note that overlaps the one
/// before it (the same note seen from both sides of a seam) is merged into it or trims it.
fn take_notes(notes: &[Note], chunk: &Chunk, out: &mut Vec<Note>) {
    for n in notes {
        let onset_s = n.onset_s + chunk.window_start_s;
        if onset_s < chunk.core_start_s || onset_s >= chunk.core_end_s {
            continue;
        }
        let mut note = *n;
        note.onset_s = onset_s;
        note.offset_s = n.offset_s + chunk.window_start_s;
        if let Some(prev) = out.last_mut() {
            if note.onset_s < prev.offset_s {
                if note.midi == prev.midi {
                    prev.offset_s = prev.offset_s.max(note.offset_s);
                    continue;
                }
                prev.offset_s = note.onset_s;
            }
        }
        out.push(note);
    }
}

impl Pipeline {
    /// Analyses an audio file of any length with bounded memory (see [`Chunking`]); files up
    /// to three minutes give exactly what [`Pipeline::analyze`] gives on the whole file.
    /// `progress` is called with the seconds analysed so far and the file's length when the
    /// container tells it.
    ///
    /// ```no_run
    /// let pipeline = violin_skeleton::Pipeline::default();
    /// let analysis = pipeline.analyze_file("concert.flac", |done_s, total_s| {
    ///     eprintln!("{done_s:.0} s of {total_s:?}");
    /// })?;
    /// # Ok::<(), violin_skeleton::Error>(())
    /// ```
    pub fn analyze_file(
        &self,
        path: impl AsRef<Path>,
        progress: impl FnMut(f64, Option<f64>),
    ) -> Result<Analysis> {
        self.analyze_file_timed(path, progress).map(|(a, _)| a)
    }

    /// [`Pipeline::analyze_file`], also telling how long each stage took.
    pub fn analyze_file_timed(
        &self,
        path: impl AsRef<Path>,
        mut progress: impl FnMut(f64, Option<f64>),
    ) -> Result<(Analysis, StageTimings)> {
        let mut timings = StageTimings::default();
        let path = path.as_ref();
        let mut reader = AudioReader::open(path)?;
        let rate = reader.sample_rate_hz();
        let total_s = reader
            .total_samples_hint()
            .map(|n| n as f64 / f64::from(rate));
        check_length(self.max_duration(), path, total_s.unwrap_or(0.0))?;
        let mut notes = Vec::new();
        let mut f0 = F0Track {
            hop_s: 0.0,
            hz: Vec::new(),
            voiced_prob: Vec::new(),
        };
        let (mut bow_changes_s, mut beats_s, mut downbeats_s) =
            (Vec::new(), Vec::new(), Vec::new());
        let mut heard_strokes: Vec<BowStroke> = Vec::new();
        let mut arousal = ArousalCurve {
            rate_hz: 2.0,
            values: Vec::new(),
        };
        let mut tempi: Vec<(f64, f64)> = Vec::new();
        let mut meter = None;
        // (confidence, seconds) of every chunk that has one.
        let mut confidences: Vec<(f64, f64)> = Vec::new();
        let (duration_s, decode_s) = for_each_chunk(&mut reader, self.chunking(), |chunk| {
            check_length(self.max_duration(), path, chunk.core_end_s)?;
            let (a, t) = self
                .analyze_timed(&chunk.audio)
                .map_err(|e| name_file(e, path))?;
            timings.add(&t);
            f0.hop_s = a.f0.hop_s;
            take_series(&a.f0.hz, a.f0.hop_s, &chunk, &mut f0.hz);
            take_series(&a.f0.voiced_prob, a.f0.hop_s, &chunk, &mut f0.voiced_prob);
            arousal.rate_hz = a.arousal.rate_hz;
            take_series(
                &a.arousal.values,
                1.0 / a.arousal.rate_hz,
                &chunk,
                &mut arousal.values,
            );
            take_notes(&a.notes, &chunk, &mut notes);
            take_events(&a.bow_changes_s, &chunk, &mut bow_changes_s);
            heard_strokes.extend(a.bow_strokes.iter().filter_map(|s| {
                let start_s = s.start_s + chunk.window_start_s;
                (start_s >= chunk.core_start_s && start_s < chunk.core_end_s).then_some(BowStroke {
                    start_s,
                    end_s: s.end_s + chunk.window_start_s,
                    ..*s
                })
            }));
            take_events(&a.beats_s, &chunk, &mut beats_s);
            take_events(&a.downbeats_s, &chunk, &mut downbeats_s);
            tempi.push((a.tempo_bpm, chunk.core_end_s - chunk.core_start_s));
            meter = meter.or(a.meter);
            if let Some(c) = a.beat_confidence {
                confidences.push((f64::from(c), chunk.core_end_s - chunk.core_start_s));
            }
            progress(chunk.core_end_s, total_s);
            Ok(())
        })?;
        drop_crowded(&mut beats_s, 0.5);
        drop_crowded(&mut downbeats_s, 0.5);
        timings.decode_s = decode_s;
        // Directions and strokes over the whole file, as for a whole analysis; the strings
        // the chunks heard are kept, and so are their directions when the bowing model
        // decodes them from the audio.
        let mut bow_directions =
            performance::heard_bow_directions(&bow_changes_s, &notes, &downbeats_s);
        if self.hears_directions()? {
            crate::strokes::keep_heard_directions(
                &bow_changes_s,
                &mut bow_directions,
                &heard_strokes,
            );
        }
        let bow_strokes = crate::strokes::strokes_with_heard_strings(
            &bow_changes_s,
            &bow_directions,
            &notes,
            &heard_strokes,
        );
        let analysis = Analysis {
            schema_version: performance::ANALYSIS_SCHEMA_VERSION,
            source: "audio".into(),
            duration_s,
            sample_rate: rate,
            f0,
            notes,
            bow_changes_s,
            bow_directions,
            bow_strokes,
            tempo_bpm_per_beat: performance::tempo_per_beat(&beats_s),
            beats_s,
            downbeats_s,
            tempo_bpm: weighted_median(&mut tempi),
            meter,
            beat_confidence: weighted_mean(&confidences),
            arousal,
        };
        Ok((analysis, timings))
    }

    /// Motion for an audio file of any length with bounded memory: [`Pipeline::analyze_file`]
    /// then synthesis for Method 2; chunk by chunk for Method 1.
    pub fn generate_file(
        &self,
        path: impl AsRef<Path>,
        progress: impl FnMut(f64, Option<f64>),
    ) -> Result<Motion> {
        match self.method() {
            Method::Rules => {
                let analysis = self.analyze_file(path, progress)?;
                self.generate_from_analysis(&analysis)
            }
            #[cfg(feature = "gru")]
            Method::Gru => self.generate_gru_file(path.as_ref(), progress),
        }
    }

    #[cfg(feature = "gru")]
    fn generate_gru_file(
        &self,
        path: &Path,
        mut progress: impl FnMut(f64, Option<f64>),
    ) -> Result<Motion> {
        let mut reader = AudioReader::open(path)?;
        let total_s = reader
            .total_samples_hint()
            .map(|n| n as f64 / f64::from(reader.sample_rate_hz()));
        check_length(self.max_duration(), path, total_s.unwrap_or(0.0))?;
        let mut frames: Vec<f32> = Vec::new();
        let mut first: Option<Motion> = None;
        let mut fps = 30.0;
        for_each_chunk(&mut reader, self.chunking(), |chunk| {
            check_length(self.max_duration(), path, chunk.core_end_s)?;
            let m = self
                .generate(&chunk.audio)
                .map_err(|e| name_file(e, path))?;
            fps = m.fps();
            let from = ((chunk.core_start_s - chunk.window_start_s) * fps).round() as usize;
            let to =
                (((chunk.core_end_s - chunk.window_start_s) * fps).round() as usize).min(m.len());
            if let Some(part) = m.frames().as_slice() {
                let per_frame = part.len() / m.len().max(1);
                frames.extend_from_slice(&part[from.min(to) * per_frame..to * per_frame]);
            }
            if first.is_none() {
                first = Some(m);
            }
            progress(chunk.core_end_s, total_s);
            Ok(())
        })?;
        let joints = skeleton::Joint::ALL.len();
        let n = frames.len() / (joints * 2);
        let array = ndarray::Array3::from_shape_vec((n, joints, 2), frames)
            .map_err(|e| crate::Error::Network(format!("gru-baseline: {e}")))?;
        let mut motion = Motion::new(fps, array)?;
        if let Some((w, h)) = first.as_ref().and_then(Motion::image_size) {
            motion = motion.with_image_size(w, h);
        }
        Ok(motion)
    }
}

/// Puts the file's name into errors that say "the recording".
fn name_file(e: Error, path: &Path) -> Error {
    match e {
        Error::TooShort {
            duration_s, min_s, ..
        } => Error::TooShort {
            source_name: path.display().to_string(),
            duration_s,
            min_s,
        },
        Error::NoNotes(_) => Error::NoNotes(path.display().to_string()),
        other => other,
    }
}

/// The tempo that covers the most time.
/// The weighted mean of `(value, weight)` pairs (`None` when there are none).
fn weighted_mean(values: &[(f64, f64)]) -> Option<f32> {
    let total: f64 = values.iter().map(|(_, w)| w).sum();
    (total > 0.0).then(|| (values.iter().map(|(v, w)| v * w).sum::<f64>() / total) as f32)
}

fn weighted_median(tempi: &mut Vec<(f64, f64)>) -> f64 {
    tempi.retain(|(t, _)| t.is_finite());
    tempi.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = tempi.iter().map(|(_, w)| w).sum();
    let mut acc = 0.0;
    for &(t, w) in tempi.iter() {
        acc += w;
        if acc >= total / 2.0 {
            return t;
        }
    }
    tempi.last().map_or(0.0, |(t, _)| *t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chunk(window_start_s: f64, core_start_s: f64, core_end_s: f64) -> Chunk {
        Chunk {
            audio: Audio::new(vec![0.0; 10], 10).unwrap(),
            window_start_s,
            core_start_s,
            core_end_s,
        }
    }

    #[test]
    fn series_from_consecutive_chunks_tile_the_file_grid() {
        let step = 0.5;
        // Window 1 starts at 0 (core 0..10), window 2 at 8 (core 10..20).
        let w1: Vec<f64> = (0..24).map(|i| i as f64 * step).collect();
        let w2: Vec<f64> = (0..24).map(|i| 8.0 + i as f64 * step).collect();
        let mut out = Vec::new();
        take_series(&w1, step, &chunk(0.0, 0.0, 10.0), &mut out);
        take_series(&w2, step, &chunk(8.0, 10.0, 20.0), &mut out);
        let expected: Vec<f64> = (0..40).map(|j| j as f64 * step).collect();
        assert_eq!(out, expected);
    }

    #[test]
    fn a_note_seen_by_two_chunks_is_kept_once() {
        let note = Note::new;
        let mut out = Vec::new();
        take_notes(
            &[note(1.0, 2.0, 60), note(9.9, 10.6, 62)],
            &chunk(0.0, 0.0, 10.0),
            &mut out,
        );
        // The second chunk's window starts at 8 s. It sees the same D a little later
        // (10.05 s, inside its core): merged into the first chunk's D. Its E is kept.
        take_notes(
            &[note(1.5, 1.9, 62), note(2.05, 2.55, 62), note(2.6, 3.0, 64)],
            &chunk(8.0, 10.0, 20.0),
            &mut out,
        );
        assert_eq!(out.len(), 3, "{out:?}");
        assert!((out[1].offset_s - 10.6).abs() < 1e-9);
        assert_eq!(out[2].midi, 64);
        assert!((out[2].onset_s - 10.6).abs() < 1e-9);
        // A different pitch starting inside the previous note trims it.
        take_notes(
            &[note(4.0, 5.0, 65), note(4.5, 5.5, 67)],
            &chunk(8.0, 10.0, 20.0),
            &mut out,
        );
        assert!((out[3].offset_s - 12.5).abs() < 1e-9, "{out:?}");
    }

    #[test]
    fn crowded_beats_at_a_seam_are_thinned() {
        let mut beats = vec![0.0, 0.5, 1.0, 1.5, 1.52, 2.0, 2.5];
        drop_crowded(&mut beats, 0.5);
        assert_eq!(beats, vec![0.0, 0.5, 1.0, 1.5, 2.0, 2.5]);
    }

    #[test]
    fn tempo_is_the_one_covering_most_time() {
        assert_eq!(
            weighted_median(&mut vec![(100.0, 120.0), (200.0, 20.0), (f64::NAN, 5.0)]),
            100.0
        );
    }
}
