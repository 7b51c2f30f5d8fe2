//! Scores of arousal predictions: Pearson r (pooled over all annotated frames) and RMSE,
//! in total and per source group.

use serde::{Deserialize, Serialize};

use crate::data::ArousalTrack;
use crate::error::Result;
use crate::estimator::{pearson, predict_with};
use crate::model::EmotionNet;

/// Predictions and targets of every track, concatenated (for a pooled Pearson r).
pub fn predictions(net: &EmotionNet, tracks: &[ArousalTrack]) -> Result<(Vec<f32>, Vec<f32>)> {
    let (mut p, mut y) = (Vec::new(), Vec::new());
    for t in tracks {
        let pred = predict_with(net, t.mel_db.view())?;
        for (k, &a) in t.arousal.iter().enumerate() {
            if let Some(&v) = pred.get(t.first_frame + k) {
                p.push(v);
                y.push(a);
            }
        }
    }
    Ok((p, y))
}

/// Pearson r and RMSE of `net` on `tracks` (pooled over all annotated frames).
pub fn score(net: &EmotionNet, tracks: &[ArousalTrack]) -> Result<(f64, f64)> {
    let (p, y) = predictions(net, tracks)?;
    let mse = p
        .iter()
        .zip(&y)
        .map(|(a, b)| f64::from(a - b).powi(2))
        .sum::<f64>()
        / p.len().max(1) as f64;
    Ok((pearson(&p, &y), mse.sqrt()))
}

/// Pearson r and RMSE of a set of tracks.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Scores {
    /// Tracks scored.
    pub tracks: usize,
    /// Their annotated length in minutes.
    pub minutes: f64,
    /// Pearson r over all annotated frames pooled.
    pub pearson_r: f64,
    /// Root mean square error.
    pub rmse: f64,
}

/// Scores over all tracks and per group (`builtin`, `soundfont`, `deam`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Evaluation {
    /// Everything.
    pub all: Scores,
    /// Per group.
    pub by_group: std::collections::BTreeMap<String, Scores>,
}

/// Scores `net` on `tracks`, in total and per group.
pub fn evaluate(net: &EmotionNet, tracks: &[ArousalTrack]) -> Result<Evaluation> {
    let scores = |ts: &[&ArousalTrack]| -> Result<Scores> {
        let owned: Vec<ArousalTrack> = ts.iter().map(|t| (*t).clone()).collect();
        let (r, rmse) = score(net, &owned)?;
        let frames: usize = ts.iter().map(|t| t.arousal.len()).sum();
        Ok(Scores {
            tracks: ts.len(),
            minutes: frames as f64 / 2.0 / 60.0,
            pearson_r: r,
            rmse,
        })
    };
    let all: Vec<&ArousalTrack> = tracks.iter().collect();
    let mut eval = Evaluation {
        all: scores(&all)?,
        by_group: Default::default(),
    };
    let mut groups: std::collections::BTreeMap<&str, Vec<&ArousalTrack>> = Default::default();
    for t in tracks {
        groups.entry(t.group.as_str()).or_default().push(t);
    }
    for (g, ts) in groups {
        eval.by_group.insert(g.to_string(), scores(&ts)?);
    }
    Ok(eval)
}
