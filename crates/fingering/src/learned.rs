//! The learned planner: an HMM-like model whose emission and transition costs are smoothed
//! log-frequencies of violinists' fingerings, decoded by Viterbi.

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::error::FingeringError;
use crate::fingering::Fingering;
use crate::learned_params::CONTEXTS;
use crate::learned_params::{LearnedParams, MAX_INTERVAL, MAX_POSITION_STEP};
use crate::physical::{self, finger_offset, position_offset};
use crate::placement::Placement;
use crate::planner::FingeringPlanner;
use crate::span::{span_class, span_cost, SpanContext, SpanTable};
use crate::string::ViolinString;
use crate::style::FingeringStyle;

/// The highest position the learned model uses on the G, D and A strings (violinists
/// number positions up to the 12th; the E string goes to the physical model's 14th).
pub const LEARNED_MAX_POSITION: u8 = 12;

const IC: usize = (2 * MAX_INTERVAL + 1) as usize;
const DS: usize = 7;
const DP: usize = (2 * MAX_POSITION_STEP + 1) as usize;

/// Every place the learned model considers for `midi`: on each string, every position
/// 1..=12 (14 on E) and every finger whose normal, low or high place (±1 semitone) plays
/// the pitch — violinists name positions by note names, so a finger may sit a semitone
/// either side of the physical model's normal place — plus the open string in every
/// position. Ordered by string, position, finger. Empty outside G3..=A7.
pub fn learned_places(midi: u8) -> Vec<Fingering> {
    let mut out = Vec::new();
    if !(physical::LOWEST_MIDI..=physical::HIGHEST_MIDI).contains(&midi) {
        return out;
    }
    for string in ViolinString::ALL {
        let Some(above) = midi.checked_sub(string.open_midi()) else {
            continue;
        };
        let top = physical::max_position(string).max(LEARNED_MAX_POSITION);
        for position in 1..=top {
            if above == 0 {
                out.push(Fingering::open(string, position));
                continue;
            }
            let base = i32::from(position_offset(position));
            for finger in 1..=4u8 {
                for placement in [Placement::Low, Placement::Normal, Placement::High] {
                    let stop =
                        base + i32::from(finger_offset(finger)) + i32::from(placement.semitones());
                    if stop == i32::from(above) {
                        out.push(Fingering::with_placement(
                            string, position, finger, placement,
                        ));
                    }
                }
            }
        }
    }
    out
}

/// The interval class of a step from `from` to `to` (MIDI).
pub(crate) fn interval_class(from: u8, to: u8) -> i8 {
    (i16::from(to) - i16::from(from)).clamp(-i16::from(MAX_INTERVAL), i16::from(MAX_INTERVAL)) as i8
}

/// String and position steps between two places, clamped to the counted classes.
pub(crate) fn steps(from: &Fingering, to: &Fingering) -> (i8, i8) {
    let ds = to.string.number() as i8 - from.string.number() as i8;
    let dp = (i16::from(to.position) - i16::from(from.position))
        .clamp(-i16::from(MAX_POSITION_STEP), i16::from(MAX_POSITION_STEP)) as i8;
    (ds, dp)
}

fn interval_bucket(from: Option<u8>, to: Option<u8>) -> usize {
    match (from, to) {
        (Some(a), Some(b)) => match i16::from(b) - i16::from(a) {
            ..=-3 => 1,
            -2..=-1 => 2,
            0 => 3,
            1..=2 => 4,
            _ => 5,
        },
        _ => 0,
    }
}

/// The melodic context of note `i` of `midi` (0..[`CONTEXTS`]).
pub fn context(midi: &[u8], i: usize) -> u8 {
    let at = |k: Option<usize>| k.and_then(|k| midi.get(k)).copied();
    let here = at(Some(i));
    let prev = interval_bucket(at(i.checked_sub(1)), here);
    let next = interval_bucket(here, at(i.checked_add(1)));
    (prev * 6 + next) as u8
}

/// Notes either side of a note whose playability in a place's hand frame is rewarded.
pub const WINDOW: usize = 4;

/// Whether `midi` can be played on `string` with the hand in `position` (an open string,
/// or a stop from a semitone below the first finger's place to one above the 4th's).
fn in_frame(midi: u8, string: ViolinString, position: u8) -> bool {
    match midi.checked_sub(string.open_midi()) {
        Some(0) => true,
        Some(above) => {
            let b = i32::from(position_offset(position));
            (b - 1..=b + 6).contains(&i32::from(above))
        }
        None => false,
    }
}

/// The neighbours of note `i` (within [`WINDOW`]) that `place`'s hand frame covers: on
/// the same string, and on any string.
fn coverage(midi: &[u8], i: usize, place: &Fingering) -> (f64, f64) {
    let (mut same, mut any) = (0.0, 0.0);
    let lo = i.saturating_sub(WINDOW);
    let hi = (i + WINDOW + 1).min(midi.len());
    for (j, &m) in midi.iter().enumerate().take(hi).skip(lo) {
        if j == i {
            continue;
        }
        if in_frame(m, place.string, place.position) {
            same += 1.0;
            any += 1.0;
        } else if ViolinString::ALL
            .iter()
            .any(|&s| in_frame(m, s, place.position))
        {
            any += 1.0;
        }
    }
    (same, any)
}

/// The model ready to decode: places and emission costs per pitch, transition costs.
#[derive(Debug)]
struct Tables {
    /// `places[midi - 55]`: the places of [`learned_places`].
    places: Vec<Vec<Fingering>>,
    /// `emission[midi - 55][place][context]`: cost in nats.
    emission: Vec<Vec<[f64; CONTEXTS]>>,
    /// `transition[interval][dstring][dposition]` in nats, times `lambda`.
    transition: Vec<f64>,
    /// `finger[interval][from][to]` in nats, times `mu`.
    finger: Vec<f64>,
    gamma_string: f64,
    gamma_position: f64,
    /// The span context and its counts, when the parameters carry one that weighs.
    span: Option<(SpanContext, SpanTable)>,
}

/// −ln of smoothed relative frequencies: `(c + w·q) / (n + w)` with `q` the back-off.
fn smoothed(count: f64, total: f64, weight: f64, backoff: f64) -> f64 {
    -((count + weight * backoff) / (total + weight)).ln()
}

impl Tables {
    fn new(p: &LearnedParams) -> Tables {
        // Emission back-off: how often (finger, placement, position) is used at all.
        let mut shape: BTreeMap<(u8, Placement, u8), f64> = BTreeMap::new();
        for ((_, _, f), &n) in &p.emission {
            *shape
                .entry((f.finger, f.placement, f.position))
                .or_default() += f64::from(n);
        }
        let mut ctx_counts: BTreeMap<(u8, Fingering), [f64; CONTEXTS]> = BTreeMap::new();
        for (&(midi, ctx, f), &n) in &p.emission {
            if let Some(c) = ctx_counts
                .entry((midi, f))
                .or_insert([0.0; CONTEXTS])
                .get_mut(usize::from(ctx))
            {
                *c += f64::from(n);
            }
        }
        let mut places = Vec::new();
        let mut emission = Vec::new();
        for midi in physical::LOWEST_MIDI..=physical::HIGHEST_MIDI {
            let list = learned_places(midi);
            let g: Vec<f64> = list
                .iter()
                .map(|f| {
                    1.0 + shape
                        .get(&(f.finger, f.placement, f.position))
                        .unwrap_or(&0.0)
                })
                .collect();
            let g_total: f64 = g.iter().sum();
            let counts: Vec<[f64; CONTEXTS]> = list
                .iter()
                .map(|f| {
                    ctx_counts
                        .get(&(midi, *f))
                        .copied()
                        .unwrap_or([0.0; CONTEXTS])
                })
                .collect();
            let n_place: Vec<f64> = counts.iter().map(|c| c.iter().sum()).collect();
            let n: f64 = n_place.iter().sum();
            let mut n_ctx = [0.0; CONTEXTS];
            for c in &counts {
                for (t, v) in n_ctx.iter_mut().zip(c) {
                    *t += v;
                }
            }
            emission.push(
                counts
                    .iter()
                    .zip(n_place.iter().zip(&g))
                    .map(|(c, (&np, &q))| {
                        let pitch_level = (np + p.alpha * q / g_total) / (n + p.alpha);
                        let mut out = [0.0; CONTEXTS];
                        for (k, o) in out.iter_mut().enumerate() {
                            *o = smoothed(c[k], n_ctx[k], p.alpha, pitch_level);
                        }
                        out
                    })
                    .collect(),
            );
            places.push(list);
        }
        let mut transition = vec![0.0; IC * DS * DP];
        let mut global = vec![1.0; DS * DP];
        for (&(_, s, d), &n) in &p.transition {
            global[(s + 3) as usize * DP + (d + MAX_POSITION_STEP) as usize] += f64::from(n);
        }
        let g_total: f64 = global.iter().sum();
        for ic in 0..IC {
            let iv = ic as i8 - MAX_INTERVAL;
            let row: Vec<f64> = (0..DS * DP)
                .map(|k| {
                    let (s, d) = ((k / DP) as i8 - 3, (k % DP) as i8 - MAX_POSITION_STEP);
                    f64::from(*p.transition.get(&(iv, s, d)).unwrap_or(&0))
                })
                .collect();
            let n: f64 = row.iter().sum();
            for (k, &c) in row.iter().enumerate() {
                transition[ic * DS * DP + k] =
                    p.lambda * smoothed(c, n, p.beta, global[k] / g_total);
            }
        }
        let mut finger = vec![0.0; IC * 25];
        let mut global = [1.0f64; 25];
        for (&(_, a, b), &n) in &p.finger {
            global[usize::from(a) * 5 + usize::from(b)] += f64::from(n);
        }
        let g_total: f64 = global.iter().sum();
        for ic in 0..IC {
            let iv = ic as i8 - MAX_INTERVAL;
            for a in 0..5u8 {
                let row: Vec<f64> = (0..5u8)
                    .map(|b| f64::from(*p.finger.get(&(iv, a, b)).unwrap_or(&0)))
                    .collect();
                let n: f64 = row.iter().sum();
                for (b, &c) in row.iter().enumerate() {
                    let q = global[usize::from(a) * 5 + b] / g_total;
                    finger[ic * 25 + usize::from(a) * 5 + b] = p.mu * smoothed(c, n, p.beta, q);
                }
            }
        }
        let span = p.span.filter(|s| s.weight > 0.0).map(|s| {
            (
                s,
                SpanTable::new(&p.span_emission, physical::LOWEST_MIDI, &places),
            )
        });
        Tables {
            span,
            gamma_string: p.gamma_string,
            gamma_position: p.gamma_position,
            places,
            emission,
            transition,
            finger,
        }
    }

    fn transition(&self, from_midi: u8, from: &Fingering, to_midi: u8, to: &Fingering) -> f64 {
        let iv = interval_class(from_midi, to_midi);
        let ic = (iv + MAX_INTERVAL) as usize;
        let (ds, dp) = steps(from, to);
        let k = ic * DS * DP + (ds + 3) as usize * DP + (dp + MAX_POSITION_STEP) as usize;
        let mut cost = self.transition.get(k).copied().unwrap_or(f64::INFINITY);
        if ds == 0 && dp == 0 && !from.is_open() && !to.is_open() {
            let f = ic * 25 + usize::from(from.finger.min(4)) * 5 + usize::from(to.finger.min(4));
            cost += self.finger.get(f).copied().unwrap_or(0.0);
        }
        cost
    }
}

/// The fingering planner learned from violinists (see `LearnedParams` and the crate
/// README): for each note, the places of [`learned_places`]; cost of a place = −ln of the
/// smoothed frequency with which violinists played that pitch there; cost of a move =
/// λ·(−ln of the smoothed frequency of that string and position step for that interval)
/// plus μ·(−ln of the finger pair's frequency) within one position and string; plus the
/// [`FingeringStyle`] knobs. Viterbi finds the plan of least total cost; ties go to the
/// place listed first, so plans are deterministic. O(n·k²) with k ≤ ~60 places per note.
///
/// ```
/// use fingering::{FingeringPlanner, LearnedPlanner};
/// let notes = [67, 69, 71, 72, 74, 76, 78, 79]; // G major, G4..G5
/// let plan = LearnedPlanner::default().plan(&notes)?;
/// assert!(plan.iter().zip(&notes).all(|(f, &m)| f.midi() == m));
/// # Ok::<(), fingering::FingeringError>(())
/// ```
#[derive(Debug, Clone)]
pub struct LearnedPlanner {
    tables: Arc<Tables>,
    style: FingeringStyle,
}

impl Default for LearnedPlanner {
    /// The shipped parameters ([`crate::LEARNED_PARAMS_TSV`]); a test checks that they
    /// parse, so the fallback to empty counts (uniform costs) is never taken.
    fn default() -> Self {
        LearnedPlanner::new(&LearnedParams::shipped().unwrap_or_default())
    }
}

impl LearnedPlanner {
    /// A planner with the given parameters and a neutral style.
    pub fn new(params: &LearnedParams) -> LearnedPlanner {
        LearnedPlanner {
            tables: Arc::new(Tables::new(params)),
            style: FingeringStyle::default(),
        }
    }

    /// The same planner with a style.
    pub fn with_style(mut self, style: FingeringStyle) -> LearnedPlanner {
        self.style = style;
        self
    }

    /// The style the planner applies.
    pub fn style(&self) -> &FingeringStyle {
        &self.style
    }

    /// The places the planner considers for `midi` (empty outside G3..=A7).
    pub fn places(&self, midi: u8) -> &[Fingering] {
        midi.checked_sub(physical::LOWEST_MIDI)
            .and_then(|i| self.tables.places.get(usize::from(i)))
            .map_or(&[], |v| v.as_slice())
    }

    /// The emission costs (nats) of `midi`'s places in melodic context `ctx`.
    fn emission(&self, midi: u8, ctx: u8) -> impl Iterator<Item = f64> + '_ {
        midi.checked_sub(physical::LOWEST_MIDI)
            .and_then(|i| self.tables.emission.get(usize::from(i)))
            .into_iter()
            .flatten()
            .map(move |c| c.get(usize::from(ctx)).copied().unwrap_or(f64::INFINITY))
    }
}

impl FingeringPlanner for LearnedPlanner {
    fn plan(&self, midi: &[u8]) -> Result<Vec<Fingering>, FingeringError> {
        for (index, &note) in midi.iter().enumerate() {
            if self.places(note).is_empty() {
                return Err(FingeringError::UnplayablePitch { index, midi: note });
            }
        }
        let mut back: Vec<Vec<u32>> = Vec::with_capacity(midi.len());
        let mut score: Vec<f64> = Vec::new();
        let mut next: Vec<f64> = Vec::new();
        let mut own: Vec<f64> = Vec::new();
        for (i, &note) in midi.iter().enumerate() {
            let places = self.places(note);
            let ctx = context(midi, i);
            let span = self.tables.span.as_ref().map(|(s, table)| {
                (
                    s,
                    table.counts((note, ctx, span_class(midi, i, s.ahead, s.behind))),
                )
            });
            own.clear();
            let emitted = places.iter().zip(self.emission(note, ctx)).enumerate();
            own.extend(emitted.map(|(k, (f, e))| {
                let e = e + span.map_or(0.0, |(s, counts)| span_cost(counts, k, e, s));
                let (same, any) = if self.tables.gamma_string + self.tables.gamma_position > 0.0 {
                    coverage(midi, i, f)
                } else {
                    (0.0, 0.0)
                };
                e + self.style.place_cost(i, f, places)
                    - self.tables.gamma_string * same
                    - self.tables.gamma_position * any
            }));
            next.clear();
            let mut from = Vec::with_capacity(places.len());
            match i.checked_sub(1).and_then(|j| midi.get(j)) {
                None => {
                    next.extend(own.iter().copied());
                    from.resize(places.len(), 0);
                }
                Some(&prev) => {
                    let prev_places = self.places(prev);
                    for (place, own) in places.iter().zip(&own) {
                        let (mut best, mut arg) = (f64::INFINITY, 0u32);
                        for (j, pf) in prev_places.iter().enumerate() {
                            let s = score[j] + self.tables.transition(prev, pf, note, place);
                            if s < best {
                                (best, arg) = (s, j as u32);
                            }
                        }
                        next.push(best + own);
                        from.push(arg);
                    }
                }
            }
            back.push(from);
            std::mem::swap(&mut score, &mut next);
        }
        let mut j = (0..score.len())
            .fold(None, |best: Option<usize>, k| match best {
                Some(b) if score[b] <= score[k] => Some(b),
                _ => Some(k),
            })
            .unwrap_or(0);
        let mut plan = vec![Fingering::open(ViolinString::G, 1); midi.len()];
        for i in (0..midi.len()).rev() {
            if let Some(&f) = self.places(midi[i]).get(j) {
                plan[i] = f;
            }
            j = back[i].get(j).map_or(0, |&b| b as usize);
        }
        Ok(plan)
    }
}
