//! Temporary: training trials with settings from the environment.
#![allow(clippy::unwrap_used, missing_docs)]
use gru_baseline::data::load_dataset;
use gru_baseline::train::{train, TrainConfig, TrainEvent, TrainOptions};
use gru_baseline::{Config, Loss, StorageDtype};

fn env<T: std::str::FromStr>(k: &str, d: T) -> T {
    std::env::var(k)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(d)
}

fn main() {
    let data = load_dataset(
        std::path::Path::new(&std::env::var("DATA").unwrap()),
        &|_, _| {},
    )
    .unwrap();
    let d = TrainConfig::default();
    let train_cfg = TrainConfig {
        epochs: env("EPOCHS", 5),
        batch_size: env("BATCH", d.batch_size),
        window_frames: env("WINDOW", d.window_frames),
        learning_rate: env("LR", d.learning_rate),
        lr_patience: env("PAT", d.lr_patience),
        early_stop_patience: env("STOP", d.early_stop_patience),
        loss: if env("UNW", 0) == 1 {
            Loss::mse()
        } else {
            Loss::default()
        },
        seed: env("SEED", 1),
        ..d
    };
    let opts = TrainOptions {
        config: Config {
            dropout: env("DROP", 0.3),
            ..Config::default()
        },
        train: train_cfg.clone(),
        out: std::env::var("OUT").unwrap().into(),
        dtype: StorageDtype::F32,
        resume: false,
        command: format!("trial {train_cfg:?}"),
        data: "trial".into(),
    };
    let t0 = std::time::Instant::now();
    train(&data, &opts, &mut |e| {
        if let TrainEvent::Epoch(r) = e {
            println!(
                "{:>6.0}s epoch {} train {:.5} val {:.5} mse {:.5} l1 {:.2} lr {:.1e}{}",
                t0.elapsed().as_secs_f64(),
                r.epoch,
                r.train_loss,
                r.val_loss.unwrap_or(0.0),
                r.val_mse.unwrap_or(0.0),
                r.val_l1_px.unwrap_or(0.0),
                r.learning_rate,
                if r.improved { " *" } else { "" }
            );
        }
    })
    .unwrap();
}
