//! Inference-side and input-side probes on the validation split (the test split is not looked
//! at): the validation Pearson r of WEIGHTS with inference windows every 10, 5, 2 and 1
//! frames, with and without a [1 2 1]/4 smoothing of the output (the proxy's own smoothing);
//! and how well a single number per frame — the frame loudness, absolute or relative to the
//! track's loudness quantile — correlates with the proxy (training + validation tracks);
//! and the validation r before and after re-estimating the batch-norm statistics with
//! dropout off (the hop figures are after it).
//!
//! ```sh
//! cargo run --release -p violin-train --example emotion_probe -- DATA_DIR [WEIGHTS]
//! ```

use emotion_net::estimator::{pearson, predict_with_hop};
use emotion_net::model::GainNorm;

fn smooth(x: &[f32]) -> Vec<f32> {
    let n = x.len();
    (0..n)
        .map(|k| (x[k.saturating_sub(1)] + 2.0 * x[k] + x[(k + 1).min(n - 1)]) / 4.0)
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = std::path::PathBuf::from(args.first().ok_or("usage: probe DATA_DIR [WEIGHTS]")?);
    let data = violin_train::emotion_data::load_dataset(&dir, &|_, _| {})?;
    for norm in [
        GainNorm::Absolute,
        GainNorm::TrackQuantile(0.5),
        GainNorm::TrackQuantile(0.9),
        GainNorm::TrackQuantile(0.95),
        GainNorm::TrackQuantile(0.99),
        GainNorm::TrackQuantile(1.0),
    ] {
        let (mut l, mut y) = (Vec::new(), Vec::new());
        for t in data.train.iter().chain(&data.val) {
            let mel = norm.apply(t.mel_db.view());
            for (k, &a) in t.arousal.iter().enumerate() {
                if let Some(row) = mel.rows().into_iter().nth(t.first_frame + k) {
                    let s: f32 = row.iter().map(|&v| 10f32.powf(v / 10.0)).sum();
                    l.push(10.0 * s.log10());
                    y.push(a);
                }
            }
        }
        println!("frame loudness {norm:?}: r {:.3}", pearson(&l, &y));
    }
    if let Some(w) = args.get(1) {
        let est = emotion_net::ArousalEstimator::load(w.as_ref())?;
        let (before, _) = emotion_net::evaluate::score(est.net(), &data.val)?;
        emotion_net::recalibrate_batch_norm(est.net(), &data.train)?;
        let (after, _) = emotion_net::evaluate::score(est.net(), &data.val)?;
        println!("batch-norm recalibration: val r {before:.3} -> {after:.3}");
        for hop in [10, 5, 2, 1] {
            let (mut p, mut ps, mut y) = (Vec::new(), Vec::new(), Vec::new());
            let t0 = std::time::Instant::now();
            for t in &data.val {
                let pred = predict_with_hop(est.net(), t.mel_db.view(), hop)?;
                let sm = smooth(&pred);
                for (k, &a) in t.arousal.iter().enumerate() {
                    if let (Some(&v), Some(&s)) =
                        (pred.get(t.first_frame + k), sm.get(t.first_frame + k))
                    {
                        p.push(v);
                        ps.push(s);
                        y.push(a);
                    }
                }
            }
            println!(
                "hop {hop:2}: val r {:.3}, smoothed {:.3} ({:.2} s)",
                pearson(&p, &y),
                pearson(&ps, &y),
                t0.elapsed().as_secs_f64()
            );
        }
    }
    Ok(())
}
