//! `input-fuzz`: seeded mutants of every input kind through the parsers (see the crate docs).
//!
//! ```sh
//! input-fuzz all --iterations 1000 --seed 1 [--timeout-s 10] [--failures DIR]
//! input-fuzz midi --iterations 200
//! ```
//!
//! `all` runs each kind in a child process and prints a table; a kind prints one line per
//! run. Exit code 0 when no mutant panicked, hung or died of a signal; 1 otherwise; 2 for a
//! bad command line.

use std::path::PathBuf;
use std::process::{Command, ExitCode};
use std::time::{Duration, Instant};

use input_fuzz::{fuzz_kind, seed_set, FuzzSettings, Kind};

struct Args {
    target: String,
    settings: FuzzSettings,
}

fn usage(message: &str) -> ExitCode {
    eprintln!("error: {message}");
    eprintln!(
        "usage: input-fuzz all|KIND [--iterations N] [--seed S] [--timeout-s T] [--failures DIR]"
    );
    let kinds: Vec<&str> = Kind::ALL.iter().map(|k| k.name()).collect();
    eprintln!("kinds: {}", kinds.join(", "));
    ExitCode::from(2)
}

fn parse(args: &[String]) -> Result<Args, String> {
    let mut it = args.iter();
    let target = it.next().cloned().ok_or("give a kind or `all`")?;
    let mut settings = FuzzSettings {
        iterations: 1000,
        seed: 1,
        timeout: Duration::from_secs(10),
        failures_dir: Some(PathBuf::from("fuzz-failures")),
    };
    while let Some(flag) = it.next() {
        let value = it.next().ok_or(format!("{flag} needs a value"))?;
        let bad = || format!("{flag} {value}: not a valid value");
        match flag.as_str() {
            "--iterations" => settings.iterations = value.parse().map_err(|_| bad())?,
            "--seed" => settings.seed = value.parse().map_err(|_| bad())?,
            "--timeout-s" => {
                let t: f64 = value.parse().map_err(|_| bad())?;
                if !(t.is_finite() && t > 0.0) {
                    return Err(bad());
                }
                settings.timeout = Duration::from_secs_f64(t);
            }
            "--failures" => settings.failures_dir = Some(PathBuf::from(value)),
            _ => return Err(format!("unknown flag {flag}")),
        }
    }
    Ok(Args { target, settings })
}

fn run_one(kind: Kind, settings: &FuzzSettings) -> ExitCode {
    let Ok(scratch) = tempfile::tempdir() else {
        eprintln!("error: cannot make a scratch folder in the temporary directory");
        return ExitCode::from(1);
    };
    let seeds = match seed_set(scratch.path()) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: cannot make the seed inputs: {e}");
            return ExitCode::from(1);
        }
    };
    let t0 = Instant::now();
    let r = fuzz_kind(kind, &seeds, scratch.path(), settings);
    println!(
        "{}\t{}\t{}\t{}\t{}\t{:.0}\t{:.0}\t{:.1}",
        r.kind,
        r.mutants,
        r.accepted,
        r.refused,
        r.panics.len(),
        r.slowest_ms,
        r.peak_rss_mib.unwrap_or(f64::NAN),
        t0.elapsed().as_secs_f64()
    );
    for (n, message) in &r.panics {
        eprintln!("PANIC {} mutant {n}: {message}", r.kind);
    }
    for e in &r.sample_errors {
        eprintln!("  {} refused: {e}", r.kind);
    }
    if r.panics.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

fn run_all(args: &[String]) -> ExitCode {
    let Ok(exe) = std::env::current_exe() else {
        eprintln!("error: cannot find this program's own path to start the kinds");
        return ExitCode::from(1);
    };
    println!("kind\tmutants\taccepted\trefused\tpanics\tslowest_ms\tpeak_rss_mib\twall_s\tstatus");
    let mut failed = false;
    for kind in Kind::ALL {
        let out = Command::new(&exe)
            .arg(kind.name())
            .args(&args[1..])
            .output();
        let (line, status) = match out {
            Ok(o) => {
                let line = String::from_utf8_lossy(&o.stdout).trim().to_string();
                let status = describe(&o.status);
                if !o.status.success() {
                    failed = true;
                    eprint!("{}", String::from_utf8_lossy(&o.stderr));
                }
                (line, status)
            }
            Err(e) => {
                failed = true;
                (kind.name().to_string(), format!("could not start ({e})"))
            }
        };
        println!("{line}\t{status}");
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

fn describe(status: &std::process::ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(signal) = status.signal() {
            return format!("killed by signal {signal}");
        }
    }
    match status.code() {
        Some(0) => "ok".into(),
        Some(3) => "hang".into(),
        Some(c) => format!("exit {c}"),
        None => "unknown".into(),
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let parsed = match parse(&args) {
        Ok(a) => a,
        Err(e) => return usage(&e),
    };
    if parsed.target == "all" {
        return run_all(&args);
    }
    match Kind::from_name(&parsed.target) {
        Some(kind) => run_one(kind, &parsed.settings),
        None => usage(&format!("unknown kind {}", parsed.target)),
    }
}
