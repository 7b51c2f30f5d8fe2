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

/// The split of a work: 10 % test, 10 % validation, 80 % train, by FNV-1a of its name.
///
/// ```
/// use corpus::schedule::work_split;
/// assert_eq!(work_split("mozart/k80"), work_split("mozart/k80"));
/// ```
pub fn work_split(work: &str) -> Split {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in work.as_bytes() {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    match h % 10 {
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
        .and_then(|p| rng.pick(p).copied());
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
