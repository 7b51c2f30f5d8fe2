//! Long files through `Pipeline::analyze_file`: decoded a piece at a time, analysed in
//! overlapping chunks and stitched, with nothing lost or doubled at the seams.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use corpus::melodies::minuet_in_g;
use corpus::render::{BowedStringSynth, RenderSettings, Renderer};
use corpus::timing::play;
use pose_preproc::metrics::match_events_s;
use violin_skeleton::fingering::OptimalPlanner;
use violin_skeleton::{Chunking, Method, Pipeline};

/// The demo minuet played twice in a row (about 49 s), as a 44.1 kHz WAV, with its onsets.
fn two_minuets(dir: &std::path::Path) -> (std::path::PathBuf, Vec<f64>, f64) {
    let mut timeline = play(&minuet_in_g(), 1);
    timeline.assign_fingering(&OptimalPlanner::default());
    let settings = RenderSettings {
        sample_rate_hz: 44_100,
        tuning_cents: 0.0,
        seed: 1,
    };
    let once = BowedStringSynth::default()
        .render(&timeline, &settings)
        .unwrap();
    let once_s = once.len() as f64 / 44_100.0;
    let mut onsets: Vec<f64> = timeline.notes.iter().map(|n| n.note.onset_s).collect();
    onsets.extend(timeline.notes.iter().map(|n| n.note.onset_s + once_s));
    let path = dir.join("two_minuets.wav");
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 44_100,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(&path, spec).unwrap();
    for s in once.iter().chain(once.iter()) {
        w.write_sample((s.clamp(-1.0, 1.0) * 32_767.0) as i16)
            .unwrap();
    }
    w.finalize().unwrap();
    (path, onsets, 2.0 * once_s)
}

#[test]
fn chunked_analysis_matches_the_music_across_seams() {
    let dir = tempfile::tempdir().unwrap();
    let (path, onsets, duration_s) = two_minuets(dir.path());
    // Cores of 12 s: four seams inside the file.
    let chunked = Pipeline::builder()
        .chunking(Chunking {
            core_s: 12.0,
            margin_s: 4.0,
        })
        .build();
    let mut calls = Vec::new();
    let a = chunked
        .analyze_file(&path, |done_s, total_s| calls.push((done_s, total_s)))
        .unwrap();
    assert!((a.duration_s - duration_s).abs() < 1e-3);
    assert!(calls.len() >= 3, "{calls:?}");
    assert!(calls.windows(2).all(|w| w[1].0 > w[0].0));
    assert!((calls.last().unwrap().1.unwrap() - duration_s).abs() < 1e-3);

    // Nothing doubled: notes in order without overlap, beats never crowded.
    assert!(a
        .notes
        .windows(2)
        .all(|w| w[1].onset_s >= w[0].offset_s - 1e-9));
    assert!(a.beats_s.windows(2).all(|w| w[1] - w[0] > 0.2));
    let found: Vec<f64> = a.notes.iter().map(|n| n.onset_s).collect();
    let m = match_events_s(&found, &onsets, 0.05);
    assert!(m.f1 > 0.85, "note onset F1 across seams {}", m.f1);

    // Series are on the file's own grid, whole.
    let whole = Pipeline::default().analyze_file(&path, |_, _| {}).unwrap();
    assert_eq!(a.f0.hop_s, whole.f0.hop_s);
    assert!((a.f0.hz.len() as i64 - whole.f0.hz.len() as i64).abs() <= 1);
    assert_eq!(a.arousal.values.len(), (duration_s * 2.0).ceil() as usize);
    let whole_f1 = match_events_s(
        &whole.notes.iter().map(|n| n.onset_s).collect::<Vec<_>>(),
        &onsets,
        0.05,
    )
    .f1;
    assert!(
        m.f1 > whole_f1 - 0.05,
        "chunked F1 {} vs whole file {whole_f1}",
        m.f1
    );
    let changes = match_events_s(&a.bow_changes_s, &whole.bow_changes_s, 0.05);
    assert!(
        changes.f1 > 0.85,
        "bow changes chunked vs whole: {}",
        changes.f1
    );
    let motion = chunked.generate_from_analysis(&a).unwrap();
    assert!((motion.duration_s() - duration_s).abs() < 0.1);
}

#[test]
fn a_short_file_is_one_chunk_and_equals_the_in_memory_analysis() {
    let dir = tempfile::tempdir().unwrap();
    let (path, _, _) = two_minuets(dir.path());
    let pipeline = Pipeline::default();
    let from_file = pipeline.analyze_file(&path, |_, _| {}).unwrap();
    let audio = violin_skeleton::load_audio(&path).unwrap();
    assert_eq!(from_file, pipeline.analyze(&audio).unwrap());
}

#[test]
fn method_one_on_a_chunked_file_covers_the_whole_file() {
    let dir = tempfile::tempdir().unwrap();
    let (path, _, duration_s) = two_minuets(dir.path());
    let pipeline = Pipeline::builder()
        .method(Method::Gru)
        .chunking(Chunking {
            core_s: 12.0,
            margin_s: 4.0,
        })
        .build();
    let motion = pipeline.generate_file(&path, |_, _| {}).unwrap();
    assert!(
        (motion.duration_s() - duration_s).abs() < 0.1,
        "{}",
        motion.duration_s()
    );
    assert!(motion.frames().iter().all(|v| v.is_finite()));
}

#[test]
fn bad_files_are_typed_errors() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = Pipeline::default();
    let missing = pipeline.analyze_file(dir.path().join("nope.wav"), |_, _| {});
    assert!(matches!(missing, Err(violin_skeleton::Error::Audio(_))));
    let not_audio = dir.path().join("notes.txt.wav");
    std::fs::write(&not_audio, "this is not audio").unwrap();
    assert!(pipeline.analyze_file(&not_audio, |_, _| {}).is_err());
    assert!(pipeline.analyze_file(dir.path(), |_, _| {}).is_err());
}
