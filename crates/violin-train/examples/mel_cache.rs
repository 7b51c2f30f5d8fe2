//! Computes and caches the 30 fps mel input of every item of a corpus
//! (`violin_train::feature_cache`), in parallel, so that training runs start at once.
//!
//! `cargo run --release -p violin-train --example mel_cache -- CORPUS_DIR`

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

fn main() {
    let Some(dir) = std::env::args().nth(1).map(PathBuf::from) else {
        eprintln!("usage: mel_cache CORPUS_DIR");
        std::process::exit(2);
    };
    let manifest = match violin_train::bowing_data::read_manifest(&dir) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    let total = manifest.items.len();
    let done = AtomicUsize::new(0);
    let started = std::time::Instant::now();
    let failures: Vec<String> = manifest
        .items
        .par_iter()
        .filter_map(|item| {
            let item_dir = dir.join(&item.dir);
            let audio = corpus::layout::item_audio(&item_dir);
            let r = violin_train::feature_cache::cached_mel30(&item_dir, &audio);
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            if n.is_multiple_of(50) || n == total {
                eprintln!(
                    "{n}/{total} items, {:.0} s",
                    started.elapsed().as_secs_f64()
                );
            }
            r.err().map(|e| format!("{}: {e}", item.dir))
        })
        .collect();
    for f in &failures {
        eprintln!("{f}");
    }
    if !failures.is_empty() {
        std::process::exit(1);
    }
}
