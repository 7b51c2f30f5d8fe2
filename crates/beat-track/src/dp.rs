//! Ellis's dynamic-programming beat tracker (Ellis 2007) with the semantics of
//! `librosa.beat.beat_track` 0.11: onsets normalised by their standard deviation, a local
//! score from a Gaussian window of ±1 beat, a cumulative score that rewards onsets and
//! penalises inter-beat intervals away from the period by `tightness · ln(Δ / period)²`,
//! the last beat chosen among local maxima of the cumulative score, and weak leading and
//! trailing beats trimmed.

/// Beat frames of `envelope` (one onset-strength value per frame) at `bpm`, with
/// `frame_rate` frames per second. Empty when the envelope is all zero or `bpm` ≤ 0.
///
/// ```
/// // Onsets every 20 frames: beats land on them (the last one may sit at the end).
/// let env: Vec<f32> = (0..400).map(|i| if i % 20 == 5 { 1.0 } else { 0.0 }).collect();
/// let beats = beat_track::track_beats(&env, 60.0 * 43.07 / 20.0, 43.07, 100.0, true);
/// assert!(beats.len() >= 19);
/// assert!(beats[..beats.len() - 1].iter().all(|b| b % 20 == 5));
/// ```
pub fn track_beats(
    envelope: &[f32],
    bpm: f64,
    frame_rate: f64,
    tightness: f64,
    trim: bool,
) -> Vec<usize> {
    track_beats_with(envelope, None, bpm, frame_rate, tightness, trim)
}

/// [`track_beats`] with `extra` (one value per frame, in units of the envelope's standard
/// deviation) added to the normalised envelope before the local score: evidence for beats
/// that is not in the onset strength, such as where long notes start.
pub fn track_beats_with(
    envelope: &[f32],
    extra: Option<&[f64]>,
    bpm: f64,
    frame_rate: f64,
    tightness: f64,
    trim: bool,
) -> Vec<usize> {
    let n = envelope.len();
    if n == 0
        || !(bpm > 0.0 && frame_rate > 0.0 && tightness > 0.0)
        || envelope.iter().all(|&v| v == 0.0)
    {
        return Vec::new();
    }
    let period = (frame_rate * 60.0 / bpm).round().max(1.0);
    let mut onsets = normalise(envelope);
    if let Some(extra) = extra {
        for (o, e) in onsets.iter_mut().zip(extra) {
            *o += e;
        }
    }
    let local = local_score(&onsets, period);
    let (backlink, cumulative) = dynamic_program(&local, period, tightness);
    let Some(tail) = last_beat(&cumulative) else {
        return Vec::new();
    };
    let mut beats = vec![false; n];
    let mut k = tail as isize;
    while k >= 0 {
        beats[k as usize] = true;
        k = backlink[k as usize];
    }
    trim_beats(&local, &mut beats, trim);
    beats
        .iter()
        .enumerate()
        .filter(|(_, &b)| b)
        .map(|(i, _)| i)
        .collect()
}

/// Divides by the standard deviation (ddof 1).
fn normalise(x: &[f32]) -> Vec<f64> {
    let n = x.len() as f64;
    let mean = x.iter().map(|&v| f64::from(v)).sum::<f64>() / n;
    let var = x
        .iter()
        .map(|&v| (f64::from(v) - mean).powi(2))
        .sum::<f64>()
        / (n - 1.0).max(1.0);
    let norm = var.sqrt() + f64::from(f32::MIN_POSITIVE);
    x.iter().map(|&v| f64::from(v) / norm).collect()
}

/// `np.convolve(onsets, gaussian(±period, σ = period / 32), "same")`.
fn local_score(onsets: &[f64], period: f64) -> Vec<f64> {
    let p = period as isize;
    let window: Vec<f64> = (-p..=p)
        .map(|k| (-0.5 * (k as f64 * 32.0 / period).powi(2)).exp())
        .collect();
    let k_len = window.len();
    let n = onsets.len();
    let half = k_len / 2;
    (0..n)
        .map(|i| {
            let lo = (i + half + 1).saturating_sub(n);
            let hi = (i + half).min(k_len);
            (lo..hi).map(|k| window[k] * onsets[i + half - k]).sum()
        })
        .collect()
}

fn dynamic_program(local: &[f64], period: f64, tightness: f64) -> (Vec<isize>, Vec<f64>) {
    let n = local.len();
    let threshold = 0.01 * local.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut backlink = vec![-1isize; n];
    let mut cumulative = vec![0.0f64; n];
    let near = round_half_even(period / 2.0) as usize;
    let far = (2.0 * period) as usize;
    // penalty[d − near] for an interval of d frames, near ≤ d ≤ far.
    let ln_period = period.ln();
    let penalty: Vec<f64> = (near..=far.max(near))
        .map(|d| tightness * ((d as f64).ln() - ln_period).powi(2))
        .collect();
    let mut first_beat = true;
    for i in 0..n {
        let mut best = f64::NEG_INFINITY;
        let mut location = -1isize;
        // Candidates from the nearest (i − near) back to the farthest (i − far); on ties the
        // nearest wins, as in librosa.
        for (k, p) in penalty.iter().enumerate() {
            let Some(loc) = i.checked_sub(near + k) else {
                break;
            };
            let score = cumulative[loc] - p;
            if score > best {
                best = score;
                location = loc as isize;
            }
        }
        cumulative[i] = if location >= 0 {
            local[i] + best
        } else {
            local[i]
        };
        if first_beat && local[i] < threshold {
            backlink[i] = -1;
        } else {
            backlink[i] = location;
            first_beat = false;
        }
    }
    (backlink, cumulative)
}

/// The last local maximum of the cumulative score that reaches half the median of all local
/// maxima.
fn last_beat(cumulative: &[f64]) -> Option<usize> {
    let n = cumulative.len();
    let is_max = |i: usize| {
        let left = if i == 0 {
            cumulative[0]
        } else {
            cumulative[i - 1]
        };
        let right = if i + 1 == n {
            cumulative[i]
        } else {
            cumulative[i + 1]
        };
        cumulative[i] > left && cumulative[i] >= right
    };
    let mut maxima: Vec<f64> = (0..n)
        .filter(|&i| is_max(i))
        .map(|i| cumulative[i])
        .collect();
    if maxima.is_empty() {
        return Some(n - 1);
    }
    maxima.sort_by(f64::total_cmp);
    let m = maxima.len();
    let median = if m % 2 == 1 {
        maxima[m / 2]
    } else {
        0.5 * (maxima[m / 2 - 1] + maxima[m / 2])
    };
    let threshold = 0.5 * median;
    (0..n)
        .rev()
        .find(|&i| is_max(i) && cumulative[i] >= threshold)
        .or(Some(n - 1))
}

/// Clears beats at the start and end whose local score is at most half the RMS of the
/// Hann-smoothed beat scores (librosa's `__trim_beats`).
fn trim_beats(local: &[f64], beats: &mut [bool], trim: bool) {
    let scores: Vec<f64> = local
        .iter()
        .zip(beats.iter())
        .filter(|(_, &b)| b)
        .map(|(s, _)| *s)
        .collect();
    let threshold = if trim && !scores.is_empty() {
        let w = [0.0, 0.5, 1.0, 0.5, 0.0];
        let k = scores.len();
        let full: Vec<f64> = (0..k + 4)
            .map(|i| {
                (0..5)
                    .filter(|&j| i >= j && i - j < k)
                    .map(|j| w[j] * scores[i - j])
                    .sum()
            })
            .collect();
        let smooth = &full[2..(local.len() + 2).min(full.len())];
        0.5 * (smooth.iter().map(|v| v * v).sum::<f64>() / smooth.len() as f64).sqrt()
    } else {
        0.0
    };
    let mut i = 0;
    while i < local.len() && local[i] <= threshold {
        beats[i] = false;
        i += 1;
    }
    let mut i = local.len();
    while i > 0 && local[i - 1] <= threshold {
        beats[i - 1] = false;
        i -= 1;
    }
}

/// Python's `round`: halves go to the even neighbour.
fn round_half_even(x: f64) -> f64 {
    let r = x.round();
    if (x - x.trunc()).abs() == 0.5 && r % 2.0 != 0.0 {
        r - x.signum()
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_envelope_has_no_beats() {
        assert!(track_beats(&[0.0; 100], 120.0, 43.0, 100.0, true).is_empty());
        assert!(track_beats(&[], 120.0, 43.0, 100.0, true).is_empty());
        assert!(track_beats(&[1.0; 10], 0.0, 43.0, 100.0, true).is_empty());
    }

    #[test]
    fn extra_evidence_picks_the_phase_of_even_onsets() {
        // Onsets every 10 frames, tracked at a period of 20: either phase fits the onsets
        // equally well. Evidence at frames ≡ 15 (mod 20) decides.
        let env: Vec<f32> = (0..400)
            .map(|i| if i % 10 == 5 { 1.0 } else { 0.0 })
            .collect();
        let extra: Vec<f64> = (0..400)
            .map(|i| if i % 20 == 15 { 1.0 } else { 0.0 })
            .collect();
        let bpm = 60.0 * 43.0 / 20.0;
        let beats = track_beats_with(&env, Some(&extra), bpm, 43.0, 100.0, false);
        assert!(beats.len() >= 18, "{beats:?}");
        // The first beat or two may sit before the tracker settles.
        let on = |beats: &[usize], phase| beats.iter().filter(|&&b| b % 20 == phase).count();
        assert!(on(&beats, 15) + 2 >= beats.len(), "{beats:?}");
        let other: Vec<f64> = (0..400)
            .map(|i| if i % 20 == 5 { 1.0 } else { 0.0 })
            .collect();
        let beats = track_beats_with(&env, Some(&other), bpm, 43.0, 100.0, false);
        assert!(on(&beats, 5) + 2 >= beats.len(), "{beats:?}");
    }

    #[test]
    fn local_score_is_a_same_convolution() {
        let s = local_score(&[0.0, 0.0, 1.0, 0.0, 0.0], 2.0);
        assert!((s[2] - 1.0).abs() < 1e-12);
        assert!(s[0] < 1e-10);
    }
}
