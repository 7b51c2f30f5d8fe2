//! Corpus statistics: how much music, how it is bowed, how fast and how loud.

use serde::{Deserialize, Serialize};

use performance::Timeline;

/// Upper edges (exclusive) of the stroke-length histogram bins, in frames at 30 fps; the
/// last bin is open-ended. 15 and 28 are the seed's partial/full-bow thresholds.
pub const STROKE_BINS_FRAMES: [u32; 6] = [8, 15, 28, 45, 60, 90];

/// Statistics over a set of items.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct CorpusStats {
    /// Items counted.
    pub items: usize,
    /// Total audio in minutes.
    pub minutes: f64,
    /// Notes per minute.
    pub notes_per_minute: f64,
    /// Share of note onsets that are bow changes (the rest are slurred).
    pub bow_change_share_of_onsets: f64,
    /// Stroke lengths (bow change to bow change) in frames: counts per bin of
    /// [`STROKE_BINS_FRAMES`] plus one open-ended bin.
    pub stroke_length_histogram: Vec<usize>,
    /// Nominal tempi: minimum, median, maximum in bpm.
    pub tempo_bpm_min_median_max: [f64; 3],
    /// Note dynamics (0 = pp, 1 = ff): minimum, median, maximum.
    pub dynamic_min_median_max: [f32; 3],
    /// Items per meter, as (meter, count).
    pub meters: Vec<(String, usize)>,
}

fn min_median_max<T: Copy + PartialOrd + Default>(mut v: Vec<T>) -> [T; 3] {
    if v.is_empty() {
        return [T::default(); 3];
    }
    v.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    [v[0], v[v.len() / 2], v[v.len() - 1]]
}

impl CorpusStats {
    /// Statistics of timelines with their meters.
    pub fn of<'a>(items: impl IntoIterator<Item = (&'a Timeline, &'a str)>) -> Self {
        let mut s = CorpusStats {
            stroke_length_histogram: vec![0; STROKE_BINS_FRAMES.len() + 1],
            ..Default::default()
        };
        let (mut notes, mut changes) = (0usize, 0usize);
        let (mut tempi, mut dynamics) = (Vec::new(), Vec::new());
        let mut meters: std::collections::BTreeMap<String, usize> = Default::default();
        for (t, meter) in items {
            s.items += 1;
            s.minutes += t.duration_s / 60.0;
            notes += t.notes.len();
            let bc = t.bow_changes_s();
            changes += bc.len();
            for w in bc.windows(2) {
                let frames = ((w[1] - w[0]) * 30.0).round() as u32;
                let bin = STROKE_BINS_FRAMES
                    .iter()
                    .position(|&edge| frames < edge)
                    .unwrap_or(STROKE_BINS_FRAMES.len());
                s.stroke_length_histogram[bin] += 1;
            }
            tempi.push(t.tempo_bpm);
            dynamics.extend(t.notes.iter().map(|n| n.dynamic));
            *meters.entry(meter.to_string()).or_default() += 1;
        }
        s.notes_per_minute = if s.minutes > 0.0 {
            notes as f64 / s.minutes
        } else {
            0.0
        };
        s.bow_change_share_of_onsets = if notes > 0 {
            changes as f64 / notes as f64
        } else {
            0.0
        };
        s.tempo_bpm_min_median_max = min_median_max(tempi);
        s.dynamic_min_median_max = min_median_max(dynamics);
        s.meters = meters.into_iter().collect();
        s
    }
}
