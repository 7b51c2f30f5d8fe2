//! A short fuzzing run of every kind (CI size; the full runs are `input-fuzz all`): no
//! mutant may panic, and each kind both accepts some inputs and refuses others, so the
//! mutator reaches past the first check and the seeds are valid.

use std::time::Duration;

use input_fuzz::{fuzz_kind, seed_set, FuzzSettings, Kind};

#[test]
fn every_kind_survives_its_mutants() {
    let scratch = tempfile::tempdir().unwrap();
    let seeds = seed_set(scratch.path()).unwrap();
    // The performance seed carries the MIDI seed's double stop (the second voice is fuzzed).
    let (_, perf) = seeds
        .by_kind
        .iter()
        .find(|(k, _)| *k == Kind::PerformanceJson)
        .unwrap();
    assert!(String::from_utf8_lossy(&perf[0]).contains("\"double_stops\""));
    let settings = FuzzSettings {
        iterations: 40,
        seed: 20261126,
        timeout: Duration::from_secs(60),
        failures_dir: None,
    };
    let mut lines = Vec::new();
    for kind in Kind::ALL {
        let dir = scratch.path().join(kind.name());
        std::fs::create_dir_all(&dir).unwrap();
        let r = fuzz_kind(kind, &seeds, &dir, &settings);
        lines.push(format!(
            "{} {}/{}/{}",
            r.kind,
            r.accepted,
            r.refused,
            r.panics.len()
        ));
        assert_eq!(r.mutants, 40, "{}", r.kind);
        assert!(r.panics.is_empty(), "{}: {:?}", r.kind, r.panics);
        assert!(r.refused > 0, "{}: no mutant was refused", r.kind);
    }
    eprintln!("{}", lines.join("\n"));
}
