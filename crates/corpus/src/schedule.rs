//! Which music and which violin each item of a many-violin corpus gets, so that splits are
//! made by **work** and by **violin**.
//!
//! Every work goes to train, validation or test by a stable hash of its name (the same works
//! are held out in every corpus, whatever its seed). Items cycle through 25 slots, visited
//! in the order of [`SLOT_ORDER`] so that even a corpus of ten items has every kind of test
//! item and a validation item:
//!
//! | slots | split | music | violin | reported as |
//! |---|---|---|---|---|
//! | 0–18 | train | études (35 %) or train works | training sources | — |
//! | 19–20 | val | études (35 %) or validation works | training sources | — |
//! | 21 | test | études | training sources | in-distribution |
//! | 22 | test | études | held-out sources | held-out violin |
//! | 23 | test | test works | training sources | held-out repertoire |
//! | 24 | test | test works | held-out sources | held-out both |
//!
//! Without repertoire, slots 23 and 24 use études (and count as slots 21 and 22).

pub use crate::manifest::HeldOut;
use crate::manifest::Split;
use crate::score::Score;
use net_core::rng::Rng;

/// FNV-1a (64-bit) of a work's name: a hash that is the same on every machine and build,
/// for splitting works.
///
/// ```
/// assert_eq!(corpus::schedule::work_hash(""), 0xcbf2_9ce4_8422_2325);
/// ```
pub fn work_hash(work: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in work.as_bytes() {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The split of a work: 10 % test, 10 % validation, 80 % train, by [`work_hash`].
///
/// ```
/// use corpus::schedule::work_split;
/// assert_eq!(work_split("mozart/k80"), work_split("mozart/k80"));
/// ```
pub fn work_split(work: &str) -> Split {
    match work_hash(work) % 10 {
        0 => Split::Test,
        1 => Split::Val,
        _ => Split::Train,
    }
}

/// The music of one item.
#[derive(Debug, Clone, PartialEq)]
pub enum Music {
    /// A generated étude with this seed.
    Etude(u64),
    /// Bars `first_bar..first_bar + bars` of repertoire score `score`.
    Excerpt {
        /// Index into the repertoire list.
        score: usize,
        /// First bar.
        first_bar: usize,
        /// Number of bars.
        bars: usize,
    },
}

/// What item `i` is made of.
#[derive(Debug, Clone, PartialEq)]
pub struct ItemPlan {
    /// Its split.
    pub split: Split,
    /// What it holds out (test items).
    pub held_out: HeldOut,
    /// The music.
    pub music: Music,
    /// Whether the violin is a held-out source.
    pub held_out_violin: bool,
}

/// Repertoire scores grouped by their work's split.
#[derive(Debug, Clone, Default)]
pub struct WorksBySplit {
    /// Indices of scores whose work is in the training split.
    pub train: Vec<usize>,
    /// … validation split.
    pub val: Vec<usize>,
    /// … test split.
    pub test: Vec<usize>,
}

impl WorksBySplit {
    /// Groups `scores` by [`work_split`] of their work.
    pub fn of(scores: &[Score]) -> Self {
        let mut w = WorksBySplit::default();
        for (i, s) in scores.iter().enumerate() {
            match work_split(&s.work) {
                Split::Train => w.train.push(i),
                Split::Val => w.val.push(i),
                Split::Test => w.test.push(i),
            }
        }
        w
    }
}

/// The order in which items visit the 25 slots: test and validation slots come early.
pub const SLOT_ORDER: [usize; 25] = [
    0, 21, 1, 19, 2, 22, 3, 23, 4, 24, 5, 6, 7, 20, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18,
];

/// Plans item `index`: its slot's split, music (drawn from `rng`) and violin family.
/// `target_s` is the wished length of an excerpt.
pub fn plan_item(
    index: usize,
    rng: &mut Rng,
    scores: &[Score],
    works: &WorksBySplit,
    target_s: f64,
) -> ItemPlan {
    let slot = SLOT_ORDER[index % 25];
    let (split, pool, held_out, violin_out): (Split, Option<&[usize]>, HeldOut, bool) = match slot {
        0..=18 => (Split::Train, Some(&works.train), HeldOut::None, false),
        19 | 20 => (Split::Val, Some(&works.val), HeldOut::None, false),
        21 => (Split::Test, None, HeldOut::None, false),
        22 => (Split::Test, None, HeldOut::Violin, true),
        23 => (Split::Test, Some(&works.test), HeldOut::Repertoire, false),
        _ => (Split::Test, Some(&works.test), HeldOut::Both, true),
    };
    let etude_seed = rng.next_u64();
    let etude_share = if slot >= 23 { 0.0 } else { 0.35 };
    let pick = pool
        .filter(|p| !p.is_empty() && !rng.chance(etude_share))
        .and_then(|p| pick_by_meter(p, scores, rng));
    let (music, held_out) = match pick.and_then(|s| scores.get(s).map(|sc| (s, sc))) {
        Some((s, score)) => (excerpt(s, score, rng, target_s), held_out),
        None => {
            // No repertoire for this slot: an étude, which is never held-out music.
            let h = match held_out {
                HeldOut::Repertoire => HeldOut::None,
                HeldOut::Both => HeldOut::Violin,
                h => h,
            };
            (Music::Etude(etude_seed), h)
        }
    };
    ItemPlan {
        split,
        held_out,
        music,
        held_out_violin: violin_out,
    }
}

/// Draws a score from `pool`, meters first: each main time signature in the pool is drawn
/// with a weight of the square root of its score count, then a score of it uniformly. Rare
/// meters (12/8, 9/8, 3/8) thus get many more items than their share of the scores, common
/// ones (2/4, 6/8) somewhat fewer.
pub fn pick_by_meter(pool: &[usize], scores: &[Score], rng: &mut Rng) -> Option<usize> {
    let mut groups: std::collections::BTreeMap<(u8, u8), Vec<usize>> = Default::default();
    for &i in pool {
        if let Some(s) = scores.get(i) {
            let ts = s.main_time_signature();
            groups
                .entry((ts.numerator, ts.denominator))
                .or_default()
                .push(i);
        }
    }
    let total: f64 = groups.values().map(|g| (g.len() as f64).sqrt()).sum();
    let mut x = rng.uniform(0.0, total);
    for g in groups.values() {
        x -= (g.len() as f64).sqrt();
        if x < 0.0 {
            return rng.pick(g).copied();
        }
    }
    groups.values().last().and_then(|g| rng.pick(g).copied())
}

/// A run of bars of `score` lasting about `target_s` at its marked tempo (or 100 beats per
/// minute), starting at a drawn bar.
fn excerpt(index: usize, score: &Score, rng: &mut Rng, target_s: f64) -> Music {
    let ts = score.main_time_signature();
    let bpm = score.tempo_bpm.unwrap_or(100.0);
    let bar_s = 60.0 / bpm * f64::from(ts.meter().beats_per_bar);
    let want = ((target_s / bar_s.max(0.1)).round() as usize).clamp(4, 48);
    let n = score.bars.len();
    let bars = want.min(n);
    let first_bar = if n > bars {
        rng.int(0, (n - bars) as i64) as usize
    } else {
        0
    };
    Music::Excerpt {
        score: index,
        first_bar,
        bars,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::score::{Bar, Provenance};
    use performance::TimeSignature;

    fn score(num: u8, den: u8) -> Score {
        Score {
            work: format!("w{num}/{den}"),
            id: String::new(),
            bars: vec![Bar {
                start_q: 0.0,
                len_q: 4.0 * f64::from(num) / f64::from(den),
                time_signature: TimeSignature::new(num, den),
            }],
            notes: Vec::new(),
            tempo_bpm: None,
            provenance: Provenance::default(),
        }
    }

    #[test]
    fn rare_meters_are_drawn_far_above_their_share() {
        let mut scores: Vec<Score> = (0..100).map(|_| score(2, 4)).collect();
        scores.push(score(12, 8));
        let pool: Vec<usize> = (0..scores.len()).collect();
        let mut rng = Rng::new(3);
        let draws = 4000;
        let rare = (0..draws)
            .filter(|_| pick_by_meter(&pool, &scores, &mut rng) == Some(100))
            .count();
        // Weights √100 : √1, so 1/11 ≈ 9 % of the draws (uniform would give 1 %).
        let share = rare as f64 / draws as f64;
        assert!((0.07..0.115).contains(&share), "12/8 share {share}");
        assert_eq!(pick_by_meter(&[], &scores, &mut rng), None);
        assert_eq!(pick_by_meter(&[100], &scores, &mut rng), Some(100));
    }
}
