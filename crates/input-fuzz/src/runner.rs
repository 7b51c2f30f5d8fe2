//! Running the mutants of one kind in this process: each mutant is written to a scratch
//! file and run with panics caught; a watchdog ends the process when one runs too long.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use violin_skeleton::Pipeline;

use crate::mutate::{below, mutate, mutate_json, Rng};
use crate::seeds::SeedSet;
use crate::targets::{run, Kind};

/// What the mutants of one kind did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct KindReport {
    /// The kind's name.
    pub kind: String,
    /// Mutants run.
    pub mutants: usize,
    /// Accepted (parsed and processed).
    pub accepted: usize,
    /// Refused with an error message.
    pub refused: usize,
    /// Panics: the mutant's number and the panic message.
    pub panics: Vec<(usize, String)>,
    /// The slowest mutant, milliseconds.
    pub slowest_ms: f64,
    /// This process's peak resident memory (VmHWM), MiB, where /proc tells it.
    pub peak_rss_mib: Option<f64>,
    /// A few distinct refusal messages, to read what users see.
    pub sample_errors: Vec<String>,
}

/// Settings of a fuzzing run.
#[derive(Debug, Clone)]
pub struct FuzzSettings {
    /// Mutants per kind.
    pub iterations: usize,
    /// The mutator's seed (mixed with the kind).
    pub seed: u64,
    /// A mutant running longer than this is a hang: the mutant is saved and the process
    /// exits with code 3.
    pub timeout: Duration,
    /// Where panicking and hanging mutants are saved (none: not saved).
    pub failures_dir: Option<PathBuf>,
}

/// Peak resident memory of this process in MiB (Linux: VmHWM of /proc/self/status).
pub fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

fn save_failure(settings: &FuzzSettings, kind: Kind, what: &str, n: usize, bytes: &[u8]) {
    if let Some(dir) = &settings.failures_dir {
        let _ = std::fs::create_dir_all(dir);
        let _ = std::fs::write(dir.join(format!("{}-{what}-{n}.bin", kind.name())), bytes);
    }
}

/// Starts the watchdog: while `started_ms` is non-zero and older than the timeout, the
/// mutant in `current` is copied to the failures folder and the process exits with code 3.
fn watchdog(
    kind: Kind,
    settings: &FuzzSettings,
    started_ms: Arc<AtomicU64>,
    current: PathBuf,
    clock: Instant,
) {
    let settings = settings.clone();
    std::thread::spawn(move || loop {
        std::thread::sleep(Duration::from_millis(100));
        let t0 = started_ms.load(Ordering::SeqCst);
        if t0 == 0 {
            continue;
        }
        let now = clock.elapsed().as_millis() as u64;
        if now.saturating_sub(t0) > settings.timeout.as_millis() as u64 {
            let bytes = std::fs::read(&current).unwrap_or_default();
            save_failure(&settings, kind, "hang", 0, &bytes);
            eprintln!(
                "HANG: a {} mutant ran longer than {:.0} s (saved in the failures folder)",
                kind.name(),
                settings.timeout.as_secs_f64()
            );
            std::process::exit(3);
        }
    });
}

/// Runs `settings.iterations` mutants of `kind`, in `scratch` (an empty folder).
pub fn fuzz_kind(
    kind: Kind,
    seeds: &SeedSet,
    scratch: &Path,
    settings: &FuzzSettings,
) -> KindReport {
    let mut report = KindReport {
        kind: kind.name().to_string(),
        ..KindReport::default()
    };
    let Some((_, kind_seeds)) = seeds.by_kind.iter().find(|(k, _)| *k == kind) else {
        return report;
    };
    let (seed, partner) = (&kind_seeds[0], &kind_seeds[kind_seeds.len() - 1]);
    let dir = scratch.join("input");
    let _ = std::fs::create_dir_all(&dir);
    if kind == Kind::OpenPose {
        for (name, bytes) in &seeds.openpose_frames {
            let _ = std::fs::write(dir.join(name), bytes);
        }
    }
    // An OpenPose mutant replaces one frame of the folder.
    let file = match (
        kind,
        seeds.openpose_frames.get(seeds.openpose_frames.len() / 2),
    ) {
        (Kind::OpenPose, Some((name, _))) => dir.join(name),
        _ => dir.join(kind.file_name()),
    };
    let pipeline = Pipeline::default();
    let mut rng = Rng::new(settings.seed ^ (kind as u64).wrapping_mul(0x0100_0000_01B3));
    let clock = Instant::now();
    let started_ms = Arc::new(AtomicU64::new(0));
    watchdog(kind, settings, started_ms.clone(), file.clone(), clock);
    let previous_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    for n in 0..settings.iterations {
        // Text formats: half the mutants keep the JSON valid and change its values.
        let bytes = if kind.is_json() && below(&mut rng, 2) == 0 {
            mutate_json(seed, partner, &mut rng)
        } else {
            let mut b = mutate(seed, partner, &mut rng);
            if kind == Kind::Ogg && below(&mut rng, 4) != 0 {
                crate::mutate::fix_ogg_crc(&mut b);
            }
            b
        };
        if std::fs::write(&file, &bytes).is_err() {
            continue;
        }
        let t = Instant::now();
        started_ms.store(
            (clock.elapsed().as_millis() as u64).max(1),
            Ordering::SeqCst,
        );
        let outcome = catch_unwind(AssertUnwindSafe(|| run(kind, &file, &dir, &pipeline)));
        started_ms.store(0, Ordering::SeqCst);
        report.slowest_ms = report.slowest_ms.max(t.elapsed().as_secs_f64() * 1e3);
        report.mutants += 1;
        match outcome {
            Ok(Ok(())) => report.accepted += 1,
            Ok(Err(message)) => {
                report.refused += 1;
                let head: String = message.chars().take(160).collect();
                if report.sample_errors.len() < 6 && !report.sample_errors.contains(&head) {
                    report.sample_errors.push(head);
                }
            }
            Err(payload) => {
                let message = payload
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "(no message)".into());
                save_failure(settings, kind, "panic", n, &bytes);
                report.panics.push((n, message));
            }
        }
    }
    std::panic::set_hook(previous_hook);
    report.peak_rss_mib = peak_rss_mib();
    report
}
