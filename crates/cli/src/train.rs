//! `violin-skeleton train bowing|emotion`: train a network on a corpus, URMP or DEAM folder.

use std::time::Instant;

use violin_skeleton::bowing_net::{self, metrics::Evaluation, TrainConfig};
use violin_skeleton::emotion_net;

use crate::contract::{check_outputs, named};
use crate::error::CliError;
use crate::train_args::{Network, TrainArgs};
use crate::train_io::{describe, epoch_line, loading_bar, write_json};
use crate::Reporter;

/// Runs `train`.
pub fn run(args: &TrainArgs, report: &Reporter) -> Result<(), CliError> {
    if args.epochs == Some(0) {
        return Err(CliError::Usage("--epochs must be at least 1".into()));
    }
    let mut inputs = vec![named("--data", &args.data)];
    for extra in &args.extra_train {
        inputs.push(named("--extra-train", extra));
    }
    if let Some(p) = &args.config {
        inputs.push(named("--config", p));
    }
    let mut outputs = vec![named("--out", &args.out)];
    if let Some(p) = &args.report {
        outputs.push(named("--report", p));
    }
    check_outputs(&inputs, &outputs)?;
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        if !parent.is_dir() {
            return Err(CliError::Output {
                path: args.out.clone(),
                reason: format!(
                    "the folder {} does not exist; create it first",
                    parent.display()
                ),
            });
        }
    }
    if args.config.is_some() && args.network == Network::Gru {
        return Err(CliError::Usage(
            "--config applies to bowing and emotion; gru takes its settings as flags".into(),
        ));
    }
    if !args.extra_train.is_empty() && args.network != Network::Bowing {
        return Err(CliError::Usage(
            "--extra-train applies to bowing only".into(),
        ));
    }
    limit_candle_threads();
    match args.network {
        Network::Bowing => train_bowing(args, report),
        Network::Emotion => train_emotion(args, report),
        Network::Gru => crate::train_gru::run(args, report),
    }
}

/// candle's element-wise ops spin-wait on a helper thread; on a busy 2-core machine that
/// wastes a core (measured: 30 % more CPU time, 20 % slower training). Matrix products keep
/// using every core. An explicit `CANDLE_NUM_THREADS` is respected.
fn limit_candle_threads() {
    if std::env::var_os("CANDLE_NUM_THREADS").is_none() {
        std::env::set_var("CANDLE_NUM_THREADS", "1");
    }
}

/// The training settings: `--config` (or the defaults), then `--epochs` and `--seed`.
fn read_config<T: serde::de::DeserializeOwned + Default>(args: &TrainArgs) -> Result<T, CliError> {
    let Some(path) = &args.config else {
        return Ok(T::default());
    };
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::Usage(format!("--config {}: cannot read ({e})", path.display())))?;
    serde_json::from_str(&text).map_err(|e| {
        CliError::Usage(format!(
            "--config {}: not {:?} training settings ({e})",
            path.display(),
            args.network
        ))
    })
}

fn train_bowing(args: &TrainArgs, report: &Reporter) -> Result<(), CliError> {
    let t0 = Instant::now();
    let bar = loading_bar(report, "loading");
    let mut data = violin_train::bowing_data::load_dataset(&args.data, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })?;
    bar.finish_and_clear();
    for extra in &args.extra_train {
        let added = violin_train::bowing_data::add_training_violin(extra, &mut data)?;
        report.line(&format!(
            "{}: {added} training recordings added",
            extra.display()
        ));
    }
    report.line(&format!(
        "{}: {} train, {} validation, {} test recordings loaded in {:.1} s",
        args.data.display(),
        data.train.len(),
        data.val.len(),
        data.test.len(),
        t0.elapsed().as_secs_f64()
    ));
    let defaults: TrainConfig = read_config(args)?;
    let cfg = TrainConfig {
        epochs: args.epochs.unwrap_or(defaults.epochs),
        seed: args.seed,
        data_description: std::iter::once(&args.data)
            .chain(&args.extra_train)
            .map(|d| describe(d))
            .collect::<Vec<_>>()
            .join(" + "),
        ..defaults
    };
    let bar = report.progress(0, "epoch");
    let mut last_f1 = None;
    let result = bowing_net::train(&data, &cfg, &args.out, args.resume, &mut |p| {
        last_f1 = p.val_f1.or(last_f1);
        bar.set_length(p.steps as u64);
        bar.set_position(p.step as u64);
        let msg = epoch_line(
            (p.epoch, p.epochs),
            p.elapsed_s,
            p.loss,
            "F1",
            last_f1.map(|last| (last, p.best_f1)),
        );
        if p.val_f1.is_some() && bar.is_hidden() {
            report.line(&msg);
        }
        bar.set_message(msg);
    })?;
    bar.finish_and_clear();
    report.line(&format!(
        "{}: trained {} epochs{} in {:.0} s; kept epoch {} (validation F1 ±2 frames {:.3}, {:.3} with the tuned decoder: threshold {:.2}, spacing {})",
        args.out.display(),
        result.epochs_run,
        if result.stopped_early { " (early stop)" } else { "" },
        result.wall_s,
        result.best_epoch + 1,
        result.best_val_f1,
        result.tuned_val_f1,
        result.decoder.threshold,
        result.decoder.min_spacing_frames
    ));
    if !data.test.is_empty() {
        let detector = bowing_net::BowChangeDetector::load(&args.out)?;
        let eval = bowing_net::metrics::evaluate(&detector, &data.test)?;
        print_bowing_eval(report, &eval);
        if let Some(path) = &args.report {
            write_json(path, &eval)?;
        }
    }
    Ok(())
}

fn train_emotion(args: &TrainArgs, report: &Reporter) -> Result<(), CliError> {
    let t0 = Instant::now();
    let bar = loading_bar(report, "loading");
    let data = violin_train::emotion_data::load_dataset(&args.data, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })?;
    bar.finish_and_clear();
    report.line(&format!(
        "{}: {} train, {} validation, {} test tracks loaded in {:.1} s",
        args.data.display(),
        data.train.len(),
        data.val.len(),
        data.test.len(),
        t0.elapsed().as_secs_f64()
    ));
    let defaults: emotion_net::TrainConfig = read_config(args)?;
    let cfg = emotion_net::TrainConfig {
        epochs: args.epochs.unwrap_or(defaults.epochs),
        seed: args.seed,
        data_description: describe(&args.data),
        ..defaults
    };
    let bar = report.progress(0, "epoch");
    let mut last_r = None;
    let result = emotion_net::train(&data, &cfg, &args.out, args.resume, &mut |p| {
        last_r = p.val_r.or(last_r);
        bar.set_length(p.steps as u64);
        bar.set_position(p.step as u64);
        let msg = epoch_line(
            (p.epoch, p.epochs),
            p.elapsed_s,
            p.loss,
            "r",
            last_r.map(|last| (last, p.best_r)),
        );
        if p.val_r.is_some() && bar.is_hidden() {
            report.line(&msg);
        }
        bar.set_message(msg);
    })?;
    bar.finish_and_clear();
    report.line(&format!(
        "{}: trained {} epochs{} in {:.0} s; kept epoch {} (validation Pearson r {:.3})",
        args.out.display(),
        result.epochs_run,
        if result.stopped_early {
            " (early stop)"
        } else {
            ""
        },
        result.wall_s,
        result.best_epoch + 1,
        result.best_val_r
    ));
    if !data.test.is_empty() {
        let est = emotion_net::ArousalEstimator::load(&args.out)?;
        let eval = emotion_net::evaluate::evaluate(est.net(), &data.test)?;
        for (group, s) in std::iter::once(("all", &eval.all))
            .chain(eval.by_group.iter().map(|(g, s)| (g.as_str(), s)))
        {
            report.line(&format!(
                "test {group}: {} tracks, {:.1} min: Pearson r {:.3}, RMSE {:.3}",
                s.tracks, s.minutes, s.pearson_r, s.rmse
            ));
        }
        if let Some(path) = &args.report {
            write_json(path, &eval)?;
        }
    }
    Ok(())
}

fn print_bowing_eval(report: &Reporter, eval: &Evaluation) {
    let line = |name: &str, s: &bowing_net::metrics::Scores| {
        format!(
            "test {name}: {} recordings, {:.1} min: F1 ±2 {:.3} (P {:.3} R {:.3}), ±3 {:.3}; onsets F1 ±3 {:.3}; slurred changes without a false change {:.3} ({} of {})",
            s.recordings,
            s.minutes,
            s.changes_2.f1(),
            s.changes_2.precision(),
            s.changes_2.recall(),
            s.changes_3.f1(),
            s.onsets_3.f1(),
            s.slur_precision(),
            s.slurred_changes - s.slurred_false_alarms,
            s.slurred_changes
        )
    };
    report.line(&line("all", &eval.all));
    for (group, s) in &eval.by_group {
        report.line(&line(group, s));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn args(network: Network, config: Option<PathBuf>) -> TrainArgs {
        TrainArgs {
            network,
            data: PathBuf::from("data"),
            out: PathBuf::from("out.safetensors"),
            epochs: None,
            resume: false,
            seed: 1,
            report: None,
            weighted: false,
            unweighted: false,
            config,
            extra_train: Vec::new(),
        }
    }

    #[test]
    fn config_files_fill_the_settings_and_bad_ones_are_usage_errors() {
        let dir = tempfile::tempdir().unwrap();
        let good = dir.path().join("settings.json");
        std::fs::write(&good, r#"{"learning_rate": 0.001, "patience": 9}"#).unwrap();
        let cfg: TrainConfig = read_config(&args(Network::Bowing, Some(good.clone()))).unwrap();
        assert_eq!((cfg.learning_rate, cfg.patience), (0.001, 9));
        assert_eq!(cfg.epochs, TrainConfig::default().epochs);
        let cfg: emotion_net::TrainConfig =
            read_config(&args(Network::Emotion, Some(good))).unwrap();
        assert_eq!(cfg.patience, 9);
        let none: TrainConfig = read_config(&args(Network::Bowing, None)).unwrap();
        assert_eq!(none, TrainConfig::default());

        let typo = dir.path().join("typo.json");
        std::fs::write(&typo, r#"{"learning_rat": 0.001}"#).unwrap();
        let e = read_config::<TrainConfig>(&args(Network::Bowing, Some(typo)))
            .unwrap_err()
            .to_string();
        assert!(e.contains("typo.json") && e.contains("learning_rat"), "{e}");
        let broken = dir.path().join("broken.json");
        std::fs::write(&broken, "{").unwrap();
        let e = read_config::<TrainConfig>(&args(Network::Bowing, Some(broken)))
            .unwrap_err()
            .to_string();
        assert!(e.contains("broken.json"), "{e}");
        let e = read_config::<TrainConfig>(&args(
            Network::Bowing,
            Some(dir.path().join("missing.json")),
        ))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("missing.json") && e.contains("cannot read"),
            "{e}"
        );
    }

    #[test]
    fn gru_refuses_a_config_file() {
        let report = Reporter { quiet: true };
        let e = run(&args(Network::Gru, Some(PathBuf::from("s.json"))), &report)
            .unwrap_err()
            .to_string();
        assert!(e.contains("--config"), "{e}");
    }
}
