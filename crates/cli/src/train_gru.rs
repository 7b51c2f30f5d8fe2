//! `violin-skeleton train gru`: Method 1 (SPEC §8) on a corpus or URMP folder.

use std::time::Instant;

use violin_skeleton::gru_baseline::eval::evaluate;
use violin_skeleton::gru_baseline::train::{train, TrainConfig, TrainEvent, TrainOptions};
use violin_skeleton::gru_baseline::{Config, GruBaseline, Loss, StorageDtype};
use violin_train::gru_data::load_dataset;

use crate::error::CliError;
use crate::train_args::TrainArgs;
use crate::train_io::{describe, loading_bar, write_json};
use crate::Reporter;

/// Runs `train gru` (the shared checks of `train` have passed).
pub fn run(args: &TrainArgs, report: &Reporter) -> Result<(), CliError> {
    let t0 = Instant::now();
    let bar = loading_bar(report, "loading");
    let data = load_dataset(&args.data, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })?;
    bar.finish_and_clear();
    report.line(&format!(
        "{}: {} train, {} validation, {} test recordings ({:.1} min of training audio) loaded in {:.1} s",
        args.data.display(),
        data.train.len(),
        data.val.len(),
        data.test.len(),
        data.train_frames() as f64 / 30.0 / 60.0,
        t0.elapsed().as_secs_f64()
    ));
    let defaults = TrainConfig::default();
    let loss = if args.unweighted {
        Loss::mse()
    } else {
        Loss::default()
    };
    let opts = TrainOptions {
        config: Config::default(),
        train: TrainConfig {
            epochs: args.epochs.unwrap_or(defaults.epochs),
            seed: args.seed,
            loss: loss.clone(),
            ..defaults
        },
        out: args.out.clone(),
        dtype: StorageDtype::F32,
        resume: args.resume,
        command: std::env::args().collect::<Vec<_>>().join(" "),
        data: format!("{} ({:?})", describe(&args.data), data.layout),
    };
    let bar = report.progress(0, "epoch");
    let mut epochs = 0;
    let summary = train(&data, &opts, &mut |e| match e {
        TrainEvent::Started {
            first_epoch,
            epochs: n,
            steps_per_epoch,
            ..
        } => {
            epochs = *n;
            bar.set_length(*steps_per_epoch as u64);
            bar.set_message(format!("epoch {first_epoch}/{n}"));
        }
        TrainEvent::Step {
            epoch,
            step,
            steps,
            loss,
        } => {
            bar.set_length(*steps as u64);
            bar.set_position(*step as u64);
            bar.set_message(format!("epoch {epoch}/{epochs} loss {loss:.4}"));
        }
        TrainEvent::Epoch(r) => {
            let val = match (r.val_loss, r.val_l1_px) {
                (Some(l), Some(px)) => format!("validation loss {l:.5}, L1 {px:.1} px"),
                _ => "no validation split".to_string(),
            };
            bar.suspend(|| {
                report.line(&format!(
                    "epoch {}: train loss {:.5}, {val}, lr {:.1e}, {:.0} s{}",
                    r.epoch,
                    r.train_loss,
                    r.learning_rate,
                    r.seconds,
                    if r.improved { " (best, saved)" } else { "" }
                ))
            });
        }
    })?;
    bar.finish_and_clear();
    let p = &summary.progress;
    report.line(&format!(
        "{}: trained {} epochs{} in {:.0} s ({} loss); kept epoch {} ({} loss {:.5})",
        args.out.display(),
        p.epochs_done,
        if summary.stopped_early {
            " (early stop)"
        } else {
            ""
        },
        p.wall_time_s,
        if loss.is_weighted() {
            "right-arm weighted"
        } else {
            "MSE"
        },
        p.best_epoch,
        if data.val.is_empty() {
            "training"
        } else {
            "validation"
        },
        p.best_loss
    ));
    if !data.test.is_empty() {
        let net = GruBaseline::load(&args.out)?;
        let scores = evaluate(&net, &data.test, &loss)?;
        report.line(&format!(
            "test: {} recordings, {:.1} min: loss {:.5}, MSE {:.5}, L1 {:.1} px per coordinate",
            data.test.len(),
            scores.frames as f64 / 1800.0,
            scores.loss,
            scores.mse,
            scores.l1_px
        ));
        if let Some(path) = &args.report {
            write_json(
                path,
                &serde_json::json!({ "record": summary.record, "history": p.history, "test": scores }),
            )?;
        }
    }
    Ok(())
}
