//! Per-frame outputs → bow changes and the string bowed between two times.
//!
//! 1. Bow changes: [`crate::Decoder`] peak picking on the change probability (threshold and
//!    minimum spacing chosen on validation data), kept only inside played stretches.
//! 2. Played stretches: the sounding stretches (input level above [`SOUNDING_DB`], gaps
//!    shorter than [`REST_FRAMES`] bridged) that are tonal: the median prominence of the
//!    frames' strongest spectral peak is at least [`TONAL_DB`], which noise never reaches.
//! 3. Strings: the string of a span is the one with the highest summed probability over
//!    its frames.
//!
//! Stroke *directions* are decoded by [`super::direction`]: the bowing rules over the
//! detected changes (`performance::heard_bow_directions`) together with the network's
//! down-bow output, when the weights carry a direction decoder.

use fingering::ViolinString;

/// The input level (dB below the recording's reference) above which a frame sounds.
pub const SOUNDING_DB: f32 = -45.0;
/// Silent frames (0.5 s at 30 fps) that make a rest, after which a stroke may be retaken.
pub const REST_FRAMES: usize = 15;
/// The median peak prominence (dB, [`super::tonal_prominence_db`]) a sounding stretch needs
/// to count as played: bowed notes give 25–45 dB, noise 8–13 dB.
pub const TONAL_DB: f32 = 16.0;

/// The played stretches `[start, end)`: [`sounding_stretches`] of the level whose median
/// peak prominence is at least [`TONAL_DB`].
pub fn played_stretches(level_db: &[f32], prominence_db: &[f32]) -> Vec<(usize, usize)> {
    sounding_stretches(level_db)
        .into_iter()
        .filter(|&(a, b)| {
            let mut p: Vec<f32> = prominence_db.get(a..b).unwrap_or(&[]).to_vec();
            if p.is_empty() {
                return false;
            }
            let mid = p.len() / 2;
            let (_, m, _) = p.select_nth_unstable_by(mid, f32::total_cmp);
            *m >= TONAL_DB
        })
        .collect()
}

/// Sounding stretches `[start, end)` of a level track, gaps shorter than a rest bridged.
pub fn sounding_stretches(level_db: &[f32]) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = Vec::new();
    let mut t = 0;
    while t < level_db.len() {
        if level_db[t] <= SOUNDING_DB {
            t += 1;
            continue;
        }
        let start = t;
        while t < level_db.len() && level_db[t] > SOUNDING_DB {
            t += 1;
        }
        match out.last_mut() {
            Some(last) if start - last.1 < REST_FRAMES => last.1 = t,
            _ => out.push((start, t)),
        }
    }
    out
}

/// The most probable string over frames `from..to` of per-frame string probabilities;
/// `None` for an empty span.
///
/// ```
/// use bowing_net::stroke::decode::string_between;
/// let p = [[0.1, 0.7, 0.1, 0.1], [0.1, 0.2, 0.6, 0.1], [0.1, 0.6, 0.2, 0.1]];
/// assert_eq!(string_between(&p, 0, 3), Some(fingering::ViolinString::D));
/// assert_eq!(string_between(&p, 3, 3), None);
/// ```
pub fn string_between(string: &[[f32; 4]], from: usize, to: usize) -> Option<ViolinString> {
    let span = string.get(from..to.min(string.len()))?;
    if span.is_empty() {
        return None;
    }
    let mut sum = [0.0f32; 4];
    for p in span {
        for (s, v) in sum.iter_mut().zip(p) {
            *s += v;
        }
    }
    let best = (0..4)
        .max_by(|&a, &b| sum[a].total_cmp(&sum[b]))
        .unwrap_or(0);
    Some(ViolinString::ALL[best])
}

/// The bow changes (fractional frames) that fall inside a played stretch.
pub fn changes_inside(changes: &[f64], stretches: &[(usize, usize)]) -> Vec<f64> {
    changes
        .iter()
        .copied()
        .filter(|&c| {
            stretches
                .iter()
                .any(|&(a, b)| c >= a as f64 - 1.0 && c < b as f64)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rests_split_stretches_and_noise_is_not_played() {
        let mut level = vec![-10.0f32; 60];
        level[20..40].iter_mut().for_each(|v| *v = -70.0);
        let stretches = played_stretches(&level, &[30.0; 60]);
        assert_eq!(stretches, [(0, 20), (40, 60)]);
        // A gap shorter than a rest is bridged.
        level[20..30].iter_mut().for_each(|v| *v = -10.0);
        level[30..40].iter_mut().for_each(|v| *v = -70.0);
        assert_eq!(played_stretches(&level, &[30.0; 60]), [(0, 60)]);
        assert!(played_stretches(&[-80.0; 30], &[30.0; 30]).is_empty());
        assert!(played_stretches(&[], &[]).is_empty());
        // Loud but not tonal (noise): not played.
        assert!(played_stretches(&[-10.0; 30], &[10.0; 30]).is_empty());
        assert_eq!(changes_inside(&[5.0, 25.0], &[(0, 10)]), [5.0]);
    }
}
