//! Chooses the bar-pointer decoder's settings for beat-net's activations on a corpus's
//! **validation** split only (the test sets are never read): beat and downbeat F (±70 ms,
//! first 5 s ignored), metre, tempo (±8 %) and double/half-tempo shares for a small grid of
//! decoding rate and tempi (`upsample`, `max_tempi`), `observation_floor`,
//! `transition_lambda`, `observation_lambda` and `max_beat_region_s`; then the bar-length
//! prior (log-probability per decoded frame added to each bar length's path before the most
//! likely one is taken), searched coordinate-wise for the best metre accuracy + downbeat F,
//! each item decoded once per bar length; last, the figures with the labelled bar length
//! (how much of the downbeat error is the bar length). The bars' phasing on bow changes is
//! the facade's and is chosen with `violin-skeleton evaluate --split val`.
//!
//! `cargo run --release -p violin-train --example tune_beats -- corpus-hook [WEIGHTS]
//! [--music etude|repertoire] [--prior-only] [--band-shifts LIST] [--score-only]
//! [--extra-val DIR]…`
//!
//! `--music repertoire` keeps the validation items of validation works (the stand-in for
//! held-out repertoire: the same figures within a few points), `--music etude` the études;
//! `--prior-only` skips the grid. `--band-shifts -2,0,2` averages the activations of the mel
//! moved by those bands (test-time averaging over the training's band-shift augmentation)
//! and `--score-only` prints the figures of the shipped decoder settings and stops.
//! `--extra-val DIR` (repeatable) pools the validation items of more corpora, e.g. the same
//! items played by the validation violins (`corpus … --validation-violin`).

use std::path::PathBuf;

use beat_net::BeatActivation;
use beat_track::bar_pointer::{decode, BarPointerBeats, BarPointerConfig};
use beat_track::eval::{beat_prf, trim_beats};
use corpus::manifest::Split;
use violin_train::beat_data::read_first_column;
use violin_train::bowing_data::read_manifest;
use violin_train::example_args::{flag_value, flag_values};
use violin_train::feature_cache::cached_mel30;

struct Item {
    act: beat_net::Activations,
    frames: f64,
    beats: Vec<f64>,
    downbeats: Vec<f64>,
    bar: Option<u64>,
    tempo: Option<f64>,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let all: Vec<String> = std::env::args().skip(1).collect();
    let music = flag_value(&all, "--music")?;
    if let Some(m) = music.filter(|m| !["etude", "repertoire"].contains(m)) {
        return Err(format!("--music {m}: give etude or repertoire").into());
    }
    let prior_only = all.iter().any(|a| a == "--prior-only");
    let score_only = all.iter().any(|a| a == "--score-only");
    let shifts: Vec<i64> = match flag_value(&all, "--band-shifts")? {
        Some(list) => list.split(',').map(str::parse).collect::<Result<_, _>>()?,
        None => vec![0],
    };
    let mut args = all
        .iter()
        .enumerate()
        .filter(|(i, a)| {
            !a.starts_with("--")
                && (*i == 0
                    || !["--music", "--band-shifts", "--extra-val"].contains(&all[i - 1].as_str()))
        })
        .map(|(_, a)| a.clone());
    let dir: PathBuf = args
        .next()
        .ok_or("usage: tune_beats CORPUS_DIR [WEIGHTS] [--music etude|repertoire] [--prior-only]")?
        .into();
    let net = match args.next() {
        Some(p) => BeatActivation::load(&PathBuf::from(p))?,
        None => BeatActivation::pretrained()?,
    };
    let mut corpora = vec![dir];
    corpora.extend(
        flag_values(&all, "--extra-val")?
            .into_iter()
            .map(PathBuf::from),
    );
    let mut items = Vec::new();
    for dir in &corpora {
        let manifest = read_manifest(dir)?;
        for it in manifest.items.iter().filter(|it| it.split == Split::Val) {
            match music {
                Some("etude") if !it.is_etude() => continue,
                Some("repertoire") if it.is_etude() => continue,
                _ => {}
            }
            let d = dir.join(&it.dir);
            let mel = cached_mel30(&d, &corpus::layout::item_audio(&d))?;
            let labels: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(d.join("labels.json"))?)?;
            let act = shifted_activations(&net, &mel, &shifts)?;
            items.push(Item {
                frames: act.beat.len() as f64,
                act,
                beats: read_first_column(&d.join("beats.txt"))?,
                downbeats: read_first_column(&d.join("downbeats.txt"))?,
                bar: labels["beats_per_bar"].as_u64(),
                tempo: violin_train::beat_data::notated_meter(&d).1,
            });
        }
    }
    println!("{} validation items", items.len());
    if score_only {
        let s = score(&items, &BarPointerConfig::default())?;
        println!(
            "band shifts {shifts:?}: beat F {:.3}  downbeat F {:.3}  metre {:.3}  tempo {:.3}  double {:.3}  half {:.3}",
            s[0], s[1], s[2], s[3], s[4], s[5]
        );
        return Ok(());
    }
    if prior_only {
        return tune_prior(&items);
    }
    println!("up tempi floor lambda_t lambda_o cap_s   beat_F  down_F  meter  tempo  double  half");
    for (upsample, max_tempi, observation_floor) in [
        (1usize, 0usize, 0.0f32),
        (2, 40, 0.0),
        (2, 40, 0.003),
        (2, 40, 0.01),
        (2, 40, 0.03),
    ] {
        for transition_lambda in [60.0, 100.0, 150.0] {
            for observation_lambda in [6.0, 8.0] {
                for max_beat_region_s in [0.0, 0.05] {
                    let base = BarPointerConfig::default();
                    let cfg = BarPointerConfig {
                        upsample,
                        max_tempi,
                        transition_lambda,
                        observation_lambda,
                        max_beat_region_s,
                        observation_floor,
                        ..base
                    };
                    let t0 = std::time::Instant::now();
                    let s = score(&items, &cfg)?;
                    println!(
                        "{upsample:>2} {max_tempi:>5} {observation_floor:>5} {transition_lambda:>8} {observation_lambda:>8} {max_beat_region_s:>5} {:>8.3} {:>7.3} {:>6.3} {:>6.3} {:>7.3} {:>5.3}  {:.1} s",
                        s[0], s[1], s[2], s[3], s[4], s[5], t0.elapsed().as_secs_f64()
                    );
                }
            }
        }
    }
    tune_prior(&items)
}

/// The activations of `mel`, averaged over copies whose bands are moved by `shifts`.
fn shifted_activations(
    net: &BeatActivation,
    mel: &ndarray::Array2<f32>,
    shifts: &[i64],
) -> Result<beat_net::Activations, Box<dyn std::error::Error>> {
    if shifts == [0] {
        return Ok(net.activations(mel.view())?);
    }
    let bands = mel.ncols();
    let mut sum: Option<beat_net::Activations> = None;
    for &k in shifts {
        let mut moved = mel.as_standard_layout().into_owned();
        let flat = moved.as_slice_mut().ok_or("mel not contiguous")?;
        net_core::frames::shift_bands(flat, bands, bands, k);
        let a = net.activations(moved.view())?;
        match &mut sum {
            None => sum = Some(a),
            Some(s) => {
                s.beat.iter_mut().zip(&a.beat).for_each(|(x, y)| *x += y);
                s.downbeat
                    .iter_mut()
                    .zip(&a.downbeat)
                    .for_each(|(x, y)| *x += y);
            }
        }
    }
    let mut s = sum.ok_or("--band-shifts is empty")?;
    let n = shifts.len() as f32;
    s.beat
        .iter_mut()
        .chain(s.downbeat.iter_mut())
        .for_each(|x| *x /= n);
    Ok(s)
}

/// Mean beat F, downbeat F, metre, tempo (±8 %), double-tempo and half-tempo shares of
/// `cfg`.
fn score(items: &[Item], cfg: &BarPointerConfig) -> Result<[f64; 6], Box<dyn std::error::Error>> {
    let mut s = [0.0; 6];
    for it in items {
        let out = decode(&it.act.beat, &it.act.downbeat, cfg)?;
        let tr = |v: &[f64]| trim_beats(v, 5.0);
        s[0] += beat_prf(&tr(&it.beats), &tr(&out.beats_s), 0.07).f_measure;
        s[1] += beat_prf(&tr(&it.downbeats), &tr(&out.downbeats_s), 0.07).f_measure;
        s[2] += f64::from(u8::from(
            it.bar == Some(out.beats_per_bar as u64) && !out.beats_s.is_empty(),
        ));
        if let Some(t) = it.tempo {
            let near = |x: f64| (out.tempo_bpm / x - 1.0).abs() <= 0.08;
            s[3] += f64::from(u8::from(near(t)));
            s[4] += f64::from(u8::from(near(2.0 * t)));
            s[5] += f64::from(u8::from(near(0.5 * t)));
        }
    }
    let n = items.len().max(1) as f64;
    Ok(s.map(|v| v / n))
}

/// (beat F, downbeat F, metre accuracy) of the decodings `per_bar[item][bar length]` with
/// `prior` per bar length, the bar length chosen as the decoder chooses it: by the
/// log-probabilities of the selection pass, `scores[item][bar length]`.
fn with_prior(
    items: &[Item],
    per_bar: &[Vec<BarPointerBeats>],
    scores: &[Vec<f64>],
    prior: &[f64],
) -> (f64, f64, f64) {
    let (mut bf, mut df, mut meter) = (0.0, 0.0, 0usize);
    let rate = BarPointerConfig::default().selection_rate() as f64;
    for ((it, decoded), scores) in items.iter().zip(per_bar).zip(scores) {
        let score = |k: usize| {
            scores.get(k).copied().unwrap_or(f64::NEG_INFINITY) + prior[k] * it.frames * rate
        };
        let best = (0..decoded.len())
            .max_by(|&a, &b| score(a).total_cmp(&score(b)))
            .unwrap_or(0);
        let out = &decoded[best];
        let tr = |v: &[f64]| trim_beats(v, 5.0);
        bf += beat_prf(&tr(&it.beats), &tr(&out.beats_s), 0.07).f_measure;
        df += beat_prf(&tr(&it.downbeats), &tr(&out.downbeats_s), 0.07).f_measure;
        meter += usize::from(it.bar == Some(out.beats_per_bar as u64) && !out.beats_s.is_empty());
    }
    let n = items.len().max(1) as f64;
    (bf / n, df / n, meter as f64 / n)
}

/// Searches the bar-length prior (steps of 0.0025 per frame in ±0.03, three rounds).
fn tune_prior(items: &[Item]) -> Result<(), Box<dyn std::error::Error>> {
    let base = BarPointerConfig {
        bar_length_prior_per_frame: Vec::new(),
        ..BarPointerConfig::default()
    };
    let mut per_bar = Vec::with_capacity(items.len());
    let mut scores = Vec::with_capacity(items.len());
    for it in items {
        scores.push(decode(&it.act.beat, &it.act.downbeat, &base)?.log_probability);
        let decoded = base
            .beats_per_bar
            .iter()
            .map(|&n| {
                let cfg = BarPointerConfig {
                    beats_per_bar: vec![n],
                    ..base.clone()
                };
                decode(&it.act.beat, &it.act.downbeat, &cfg)
            })
            .collect::<Result<Vec<_>, _>>()?;
        per_bar.push(decoded);
    }
    let mut prior = vec![0.0; base.beats_per_bar.len()];
    let start = with_prior(items, &per_bar, &scores, &prior);
    println!("\nbar lengths {:?}", base.beats_per_bar);
    println!(
        "no prior: beat F {:.3}  downbeat F {:.3}  metre {:.3}",
        start.0, start.1, start.2
    );
    let objective = |s: (f64, f64, f64)| s.2 + s.1;
    let mut best = objective(start);
    for _round in 0..3 {
        for k in 0..prior.len() {
            for step in -12..=12 {
                let mut p = prior.clone();
                p[k] = f64::from(step) * 0.0025;
                let s = with_prior(items, &per_bar, &scores, &p);
                if objective(s) > best + 1e-9 {
                    best = objective(s);
                    prior = p;
                }
            }
        }
    }
    let s = with_prior(items, &per_bar, &scores, &prior);
    println!(
        "prior {prior:?}: beat F {:.3}  downbeat F {:.3}  metre {:.3}",
        s.0, s.1, s.2
    );
    // The bar length given (the label's, when it is one of those tried): how much of the
    // downbeat error is the bar length and how much the bar's phase.
    let (mut bf, mut df, mut m) = (0.0, 0.0, 0usize);
    for (it, decoded) in items.iter().zip(&per_bar) {
        let k = base
            .beats_per_bar
            .iter()
            .position(|&n| Some(n as u64) == it.bar);
        let out = &decoded[k.unwrap_or(0)];
        let tr = |v: &[f64]| trim_beats(v, 5.0);
        bf += beat_prf(&tr(&it.beats), &tr(&out.beats_s), 0.07).f_measure;
        df += beat_prf(&tr(&it.downbeats), &tr(&out.downbeats_s), 0.07).f_measure;
        m += usize::from(k.is_some());
    }
    let n = items.len() as f64;
    println!(
        "oracle bar length: beat F {:.3} downbeat F {:.3} metre {:.3}",
        bf / n,
        df / n,
        m as f64 / n
    );
    Ok(())
}
