//! A many-violin corpus with repertoire: splits by work and violin, labels, determinism,
//! and the bad inputs the builder must refuse or skip.

use std::path::Path;

use corpus::build::{build_corpus, CorpusConfig, RendererChoice};
use corpus::manifest::Split;
use corpus::repertoire::{read_dir, read_score};
use corpus::schedule::{work_split, HeldOut};

fn tiny_repertoire(dir: &Path) -> std::io::Result<()> {
    // Two short tunes in 6/8 and 3/8 with a pickup, slurs, a fermata and double stops (every
    // fourth note, a sixth below), in the score schema.
    for (name, num, den, pickup) in [("jig", 6u8, 8u8, 0.5), ("waltz", 3, 8, 0.0)] {
        let bar_q = f64::from(num) * 4.0 / f64::from(den);
        let mut bars = vec![
            serde_json::json!({"start_q": 0.0, "len_q": if pickup > 0.0 { pickup } else { bar_q }, "numerator": num, "denominator": den}),
        ];
        let mut start = if pickup > 0.0 { pickup } else { bar_q };
        for _ in 0..12 {
            bars.push(serde_json::json!({"start_q": start, "len_q": bar_q, "numerator": num, "denominator": den}));
            start += bar_q;
        }
        let mut notes = Vec::new();
        let mut q = 0.0;
        let mut k = 0;
        while q < start - 1e-9 {
            notes.push(serde_json::json!({
                "start_q": q, "dur_q": 0.5,
                "midi": if k % 4 == 3 { vec![67 + (k * 5) % 12, 58 + (k * 5) % 12] } else { vec![67 + (k * 5) % 12] },
                "slurred": k % 3 == 1, "staccato": k % 7 == 0, "accent": false,
                "fermata": q + 0.5 >= start - 1e-9, "dynamic": null
            }));
            q += 0.5;
            k += 1;
        }
        let score = serde_json::json!({
            "schema": "violin-skeleton-score/1", "id": format!("test/{name}"),
            "work": format!("test/{name}"), "collection": "test", "title": name,
            "source": "generated in tests/many.rs", "license": "ours", "tempo_qpm": null,
            "bars": bars, "notes": notes
        });
        std::fs::write(dir.join(format!("{name}.json")), score.to_string())?;
    }
    std::fs::write(dir.join("broken.json"), "{\"schema\": ")?;
    let reserved = std::fs::read_to_string(dir.join("jig.json"))?
        .replace("test/jig", "mozart/k458/movement1/violin1");
    std::fs::write(dir.join("reserved.json"), reserved)
}

fn sf2_dir() -> &'static Path {
    let d = Path::new(corpus::violins::SYSTEM_SF2_DIR);
    assert!(
        ["FluidR3_GM.sf2", "TimGM6mb.sf2", "sf_GMbank.sf2"]
            .iter()
            .all(|f| d.join(f).is_file()),
        "the Debian SoundFonts are missing: apt-get install fluid-soundfont-gm timgm6mb-soundfont csound-soundfont (.ci/run installs them)"
    );
    d
}

/// A many-violin corpus config over the tiny repertoire written into `rep`.
fn many_config(rep: &Path, minutes: f64, seed: u64) -> std::io::Result<CorpusConfig> {
    tiny_repertoire(rep)?;
    Ok(CorpusConfig {
        minutes,
        seed,
        renderer: RendererChoice::Many(sf2_dir().to_path_buf()),
        repertoire: Some(rep.to_path_buf()),
        ..CorpusConfig::default()
    })
}

#[test]
fn repertoire_reader_skips_broken_and_reserved_files() {
    let dir = tempfile::tempdir().unwrap();
    tiny_repertoire(dir.path()).unwrap();
    let (scores, skipped) = read_dir(dir.path()).unwrap();
    assert_eq!(scores.len(), 2);
    assert_eq!(skipped.len(), 2, "{skipped:?}");
    assert!(skipped.iter().any(|s| s.reason.contains("reserved")));
    assert!(skipped
        .iter()
        .any(|s| s.reason.contains("not a score file")));
    let jig = read_score(&dir.path().join("jig.json")).unwrap();
    // 6/8 with a one-eighth pickup: beats are dotted quarters, the pickup has no beat.
    let beats = jig.beats_q();
    assert!((beats[0].0 - 0.5).abs() < 1e-9 && beats[0].1);
    assert!((beats[1].0 - 2.0).abs() < 1e-9 && !beats[1].1);
    let waltz = read_score(&dir.path().join("waltz.json")).unwrap();
    // 3/8: one beat per bar, every beat a downbeat.
    assert!(waltz.beats_q().iter().all(|(_, down)| *down));
    assert!(read_dir(&dir.path().join("missing")).is_err());
}

#[test]
fn many_violin_corpus_splits_by_work_and_violin() {
    let rep = tempfile::tempdir().unwrap();
    let out = tempfile::tempdir().unwrap();
    let cfg = many_config(rep.path(), 2.5, 4).unwrap();
    let m = build_corpus(out.path(), &cfg, &|_, _| {}).unwrap();
    assert!(m.stats.minutes >= 2.5, "{} min", m.stats.minutes);
    assert!(
        m.double_stops_played > 0 && m.chord_pitches_dropped > 0,
        "double stops played {}, pitches dropped {}",
        m.double_stops_played,
        m.chord_pitches_dropped
    );
    assert_eq!(m.skipped_scores.len(), 2);
    let held: Vec<_> = m
        .violins
        .iter()
        .filter(|v| v.held_out)
        .map(|v| v.name.clone())
        .collect();
    assert_eq!(held.len(), 2);
    for it in &m.items {
        let violin_out = held.contains(&it.violin);
        // Held-out violins play only test items, and only the violin/both sets.
        if violin_out {
            assert_eq!(it.split, Split::Test);
            assert!(matches!(it.held_out, HeldOut::Violin | HeldOut::Both));
        }
        if matches!(it.held_out, HeldOut::Repertoire | HeldOut::Both) {
            assert_eq!(work_split(&it.work), Split::Test);
        }
        if it.split == Split::Train && !it.work.starts_with("etude/") {
            assert_eq!(work_split(&it.work), Split::Train);
        }
        // Every bow change lies on a note onset; strokes alternate or retake.
        let dir = out.path().join(&it.dir);
        let onsets: Vec<f64> = std::fs::read_to_string(dir.join("notes.tsv"))
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split('\t').next().unwrap().parse().unwrap())
            .collect();
        for line in std::fs::read_to_string(dir.join("bowchanges.txt"))
            .unwrap()
            .lines()
        {
            let t: f64 = line.parse().unwrap();
            assert!(onsets.iter().any(|o| (o - t).abs() < 1e-5));
        }
        // Every double stop sounds with a melody note, one string lower.
        let notes = std::fs::read_to_string(dir.join("notes.tsv")).unwrap();
        let melody: Vec<Vec<&str>> = notes
            .lines()
            .skip(1)
            .map(|l| l.split('\t').collect())
            .collect();
        for l in std::fs::read_to_string(dir.join("double_stops.tsv"))
            .unwrap()
            .lines()
            .skip(1)
        {
            let second: Vec<&str> = l.split('\t').collect();
            let top = melody.iter().find(|m| m[0] == second[0]).unwrap();
            let (top_string, string): (u8, u8) =
                (top[3].parse().unwrap(), second[3].parse().unwrap());
            assert_eq!(string + 1, top_string, "{l}");
            assert!(second[2].parse::<u8>().unwrap() < top[2].parse::<u8>().unwrap());
        }
        let strokes = std::fs::read_to_string(dir.join("strokes.tsv")).unwrap();
        assert_eq!(
            strokes.lines().count() - 1,
            std::fs::read_to_string(dir.join("bowchanges.txt"))
                .unwrap()
                .lines()
                .count()
        );
    }
    let sets: std::collections::BTreeSet<_> = m
        .items
        .iter()
        .filter(|i| i.split == Split::Test)
        .map(|i| i.held_out)
        .collect();
    assert!(
        sets.contains(&HeldOut::None) && sets.contains(&HeldOut::Violin),
        "{sets:?}"
    );
    // Same seed, same bytes.
    let again = tempfile::tempdir().unwrap();
    build_corpus(again.path(), &cfg, &|_, _| {}).unwrap();
    let lossy = m.items.iter().filter(|i| i.audio != "audio.wav").count();
    let stereo = m
        .items
        .iter()
        .filter(|i| i.recording.as_ref().is_some_and(|r| r.channels == 2))
        .count();
    assert!(lossy > 0 && stereo > 0, "lossy {lossy}, stereo {stereo}");
    for it in m.items.iter().take(6) {
        assert!(out.path().join(&it.dir).join(&it.audio).is_file());
        for f in [
            it.audio.as_str(),
            "notes.tsv",
            "double_stops.tsv",
            "strokes.tsv",
            "labels.json",
        ] {
            assert_eq!(
                std::fs::read(out.path().join(&it.dir).join(f)).unwrap(),
                std::fs::read(again.path().join(&it.dir).join(f)).unwrap(),
                "{} {f}",
                it.dir
            );
        }
    }
}

#[test]
fn a_validation_violin_renders_only_the_validation_items_with_the_same_labels() {
    let rep = tempfile::tempdir().unwrap();
    let fonts = tempfile::tempdir().unwrap();
    let violin = fonts.path().join("tiny.sf2");
    std::fs::write(&violin, corpus::render::tiny_violin_sf2()).unwrap();
    let cfg = many_config(rep.path(), 2.0, 5).unwrap();
    let (plain, heard) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let m = build_corpus(plain.path(), &cfg, &|_, _| {}).unwrap();
    let with_violin = CorpusConfig {
        validation_violin: Some(violin.clone()),
        ..cfg.clone()
    };
    let v = build_corpus(heard.path(), &with_violin, &|_, _| {}).unwrap();
    let val: Vec<_> = m.items.iter().filter(|i| i.split == Split::Val).collect();
    assert!(!val.is_empty());
    assert_eq!(v.items.len(), val.len());
    assert_eq!(v.violins.len(), 1);
    for (a, b) in val.iter().zip(&v.items) {
        assert_eq!(
            (a.dir.as_str(), b.split, b.violin.as_str()),
            (b.dir.as_str(), Split::Val, "validation:tiny")
        );
        for f in ["notes.tsv", "bowchanges.txt", "strokes.tsv", "labels.json"] {
            assert_eq!(
                std::fs::read(plain.path().join(&a.dir).join(f)).unwrap(),
                std::fs::read(heard.path().join(&b.dir).join(f)).unwrap(),
                "{} {f}",
                a.dir
            );
        }
    }
    // A file that is neither a GUS patch nor an SF2 is refused with its path.
    let bogus = fonts.path().join("bogus.pat");
    std::fs::write(&bogus, b"not a patch").unwrap();
    let e = build_corpus(
        tempfile::tempdir().unwrap().path(),
        &CorpusConfig {
            validation_violin: Some(bogus),
            ..cfg
        },
        &|_, _| {},
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("bogus.pat") && e.contains("GUS patch"), "{e}");
}

#[test]
fn a_training_violin_renders_only_the_training_items_from_a_sample_folder() {
    let rep = tempfile::tempdir().unwrap();
    let samples = tempfile::tempdir().unwrap();
    // A folder of two per-note recordings (saw-like tones at G3 and A4).
    for (name, hz) in [("G3.wav", 196.0), ("A4.wav", 440.0)] {
        let spec = hound::WavSpec {
            channels: 1,
            sample_rate: 22_050,
            bits_per_sample: 16,
            sample_format: hound::SampleFormat::Int,
        };
        let mut w = hound::WavWriter::create(samples.path().join(name), spec).unwrap();
        for i in 0..22_050 {
            let t = i as f64 * hz / 22_050.0;
            w.write_sample(((t.fract() - 0.5) * 16_000.0) as i16)
                .unwrap();
        }
        w.finalize().unwrap();
    }
    let cfg = many_config(rep.path(), 2.0, 5).unwrap();
    let (plain, heard) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let m = build_corpus(plain.path(), &cfg, &|_, _| {}).unwrap();
    let with_violin = CorpusConfig {
        training_violin: Some(samples.path().to_path_buf()),
        ..cfg.clone()
    };
    let v = build_corpus(heard.path(), &with_violin, &|_, _| {}).unwrap();
    let train: Vec<_> = m.items.iter().filter(|i| i.split == Split::Train).collect();
    assert!(!train.is_empty());
    assert_eq!(v.items.len(), train.len());
    assert_eq!(v.violins.len(), 1);
    assert!(!v.violins[0].held_out);
    for (a, b) in train.iter().zip(&v.items) {
        assert_eq!((a.dir.as_str(), b.split), (b.dir.as_str(), Split::Train));
        assert!(b.violin.starts_with("training:"), "{}", b.violin);
        assert_eq!(
            std::fs::read(plain.path().join(&a.dir).join("labels.json")).unwrap(),
            std::fs::read(heard.path().join(&b.dir).join("labels.json")).unwrap(),
        );
    }
    // Both recasts at once are refused, and so is a folder with no note file.
    let both = CorpusConfig {
        validation_violin: Some(samples.path().join("G3.wav")),
        ..with_violin
    };
    let e = build_corpus(tempfile::tempdir().unwrap().path(), &both, &|_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("two folders"), "{e}");
    let empty = tempfile::tempdir().unwrap();
    let e = build_corpus(
        tempfile::tempdir().unwrap().path(),
        &CorpusConfig {
            training_violin: Some(empty.path().to_path_buf()),
            ..cfg.clone()
        },
        &|_, _| {},
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("no file named by a note"), "{e}");
    // An SF2 with a program after a colon plays that program, or is refused without it.
    let fonts = tempfile::tempdir().unwrap();
    let sf2 = fonts.path().join("tiny.sf2");
    std::fs::write(&sf2, corpus::render::tiny_violin_sf2()).unwrap();
    let e = build_corpus(
        tempfile::tempdir().unwrap().path(),
        &CorpusConfig {
            training_violin: Some(format!("{}:41", sf2.display()).into()),
            ..cfg.clone()
        },
        &|_, _| {},
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("tiny.sf2") && e.contains("no GM program 41"),
        "{e}"
    );
    let v = build_corpus(
        tempfile::tempdir().unwrap().path(),
        &CorpusConfig {
            training_violin: Some(format!("{}:40", sf2.display()).into()),
            ..cfg
        },
        &|_, _| {},
    )
    .unwrap();
    assert_eq!(v.violins[0].name, "training:tiny");
}

#[test]
fn a_missing_soundfont_folder_is_refused_with_its_path() {
    let out = tempfile::tempdir().unwrap();
    let cfg = CorpusConfig {
        minutes: 1.0,
        renderer: RendererChoice::Many("/nonexistent/sf2".into()),
        ..CorpusConfig::default()
    };
    let e = build_corpus(out.path(), &cfg, &|_, _| {})
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("/nonexistent/sf2") && e.contains("install"),
        "{e}"
    );
}
