//! The bow planner (SPEC §5): bow changes → strokes → bow position per frame.
//!
//! Bow position `p` runs from 0 (the frog at the string) to 1 (the tip at the string). A
//! down-bow moves `p` up, an up-bow moves it down; the stroke reverses at every change.
//!
//! # Algorithm
//!
//! 1. **Strokes.** The change times are rounded to frames; changes at frame 0, at or after
//!    the last frame, or on the same frame as another are dropped. Stroke *i* runs from one
//!    change to the next (the first from frame 0, the last to the end), `n_i` frames long.
//! 2. **Desired travel** (the original rule, [`BowPolicy`]): a stroke shorter than
//!    `partial_below_frames` (15) travels at full-bow speed for its own length,
//!    `T_i = n_i / full_bow_frames` (28); a longer one travels the whole bow, `T_i = 1`.
//! 3. **Direction.** Given per stroke ([`plan_bow_directed`], e.g. from the stroke
//!    network: a stroke that keeps the previous direction is a retake and may start
//!    anywhere), or alternating ([`plan_bow`]), where only the first one is free: it is a
//!    down-bow unless starting with an up-bow puts more downbeats on down-bows (a downbeat
//!    belongs to the stroke that starts within ±2 frames of it, else to the stroke in
//!    progress).
//! 4. **Distribution (look-ahead).** Followed literally, the rule drifts out of the bow
//!    after a few unequal strokes (see [`plan_naive`]). Instead the planner chooses every
//!    stroke's start and actual travel `t_i` jointly by dynamic programming (Viterbi) over
//!    bow positions on a grid of `resolution` steps: positions stay in [0, 1] by
//!    construction, `t_i` may range from 0 to `min(1, max_speed_factor · n_i /
//!    full_bow_frames)` (a short note may be bowed faster, as players do), and the cost
//!    `Σ (t_i − T_i)² / T_i + start_weight · |p_0 − p_pref|` is minimised over the whole
//!    piece, where `p_pref` is the frog for a first down-bow and the tip for a first up-bow.
//!    The result is the globally best distribution: each stroke starts where the following
//!    strokes fit.
//! 5. **Speed profile.** Within a stroke the bow eases in and out: the speed is
//!    `reversal_speed` × cruise at both ends and rises to cruise along smoothstep ramps that
//!    take `ramp_fraction` of the stroke, so the speed is continuous inside a stroke and
//!    jumps only at the reversal itself (from `+e·v` to `−e·v'`). The position at a change
//!    frame is the extreme of the two strokes around it.

use crate::bow_profile::sample_strokes;
pub use crate::bow_stroke::{BowDirection, BowPolicy, PlannedStroke};
use crate::error::Result;

/// Planned strokes and the bow position of every frame.
#[derive(Debug, Clone, PartialEq)]
pub struct BowPlan {
    strokes: Vec<PlannedStroke>,
    positions: Vec<f32>,
}

impl BowPlan {
    /// The strokes in order.
    pub fn strokes(&self) -> &[PlannedStroke] {
        &self.strokes
    }

    /// Bow position per frame (0 frog … 1 tip).
    pub fn positions(&self) -> &[f32] {
        &self.positions
    }

    /// The frames where a stroke starts (the bow changes that were kept).
    pub fn change_frames(&self) -> Vec<usize> {
        self.strokes.iter().skip(1).map(|s| s.start_frame).collect()
    }
}

/// Change times (s) → sorted, deduplicated change frames strictly inside `(0, frames)`.
pub fn change_frames(changes_s: &[f64], fps: f64, frames: usize) -> Vec<usize> {
    let mut out: Vec<usize> = changes_s
        .iter()
        .filter(|t| t.is_finite())
        .map(|t| (t * fps).round().max(0.0) as usize)
        .filter(|&f| f > 0 && f < frames)
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

fn stroke_bounds(changes: &[usize], frames: usize) -> Vec<(usize, usize)> {
    let mut bounds = Vec::with_capacity(changes.len() + 1);
    let mut start = 0;
    for &c in changes.iter().filter(|&&c| c > 0 && c < frames) {
        if c > start {
            bounds.push((start, c));
            start = c;
        }
    }
    bounds.push((start, frames));
    bounds
}

/// Picks the first stroke's direction (step 3 of the module's algorithm).
fn first_direction(
    bounds: &[(usize, usize)],
    downbeat_frames: &[f64],
    policy: &BowPolicy,
) -> BowDirection {
    if !policy.prefer_down_on_downbeats || downbeat_frames.is_empty() {
        return BowDirection::Down;
    }
    // Count downbeats whose stroke has an even index (same direction as the first stroke).
    let (mut even, mut odd) = (0usize, 0usize);
    for &d in downbeat_frames {
        let starting = bounds
            .iter()
            .position(|&(a, _)| (a as f64 - d).abs() <= 2.0);
        let current = bounds
            .iter()
            .position(|&(a, b)| (a as f64) <= d && d < b as f64);
        if let Some(i) = starting.or(current) {
            if i % 2 == 0 {
                even += 1;
            } else {
                odd += 1;
            }
        }
    }
    if odd > even {
        BowDirection::Up
    } else {
        BowDirection::Down
    }
}

/// Plans the bow for `frames` frames with strokes reversing at `changes` (frame indices),
/// preferring down-bows on `downbeat_frames` (fractional frame positions). See the module
/// documentation for the algorithm.
///
/// ```
/// use motion_synth::bow::{plan_bow, BowPolicy};
/// let plan = plan_bow(&[40, 45, 50, 90], 120, &[], &BowPolicy::default())?;
/// assert_eq!(plan.positions().len(), 120);
/// assert!(plan.positions().iter().all(|p| (0.0..=1.0).contains(p)));
/// assert_eq!(plan.change_frames(), vec![40, 45, 50, 90]);
/// # Ok::<(), motion_synth::SynthError>(())
/// ```
pub fn plan_bow(
    changes: &[usize],
    frames: usize,
    downbeat_frames: &[f64],
    policy: &BowPolicy,
) -> Result<BowPlan> {
    plan_with(changes, frames, policy, |bounds| {
        let mut dir = first_direction(bounds, downbeat_frames, policy);
        bounds
            .iter()
            .map(|_| {
                let d = dir;
                dir = dir.reversed();
                d
            })
            .collect()
    })
}

/// [`plan_bow`] with the direction of every stroke given (e.g. by the stroke network):
/// `direction_at(frame)` is asked for each stroke's middle frame. Where a stroke keeps
/// the direction of the one before (a retake: the bow is lifted and set down again), the
/// planner may start it anywhere, preferring the frog for a down-bow and the tip for an
/// up-bow (`start_weight`), instead of where the previous stroke ended.
///
/// ```
/// use motion_synth::bow::{plan_bow_directed, BowDirection, BowPolicy};
/// let down = |_f: usize| BowDirection::Down;
/// let plan = plan_bow_directed(&[40, 80], 120, down, &BowPolicy::default())?;
/// assert!(plan.strokes().iter().all(|s| s.direction == BowDirection::Down));
/// assert!(plan.positions().iter().all(|p| (0.0..=1.0).contains(p)));
/// # Ok::<(), motion_synth::SynthError>(())
/// ```
pub fn plan_bow_directed(
    changes: &[usize],
    frames: usize,
    direction_at: impl Fn(usize) -> BowDirection,
    policy: &BowPolicy,
) -> Result<BowPlan> {
    plan_with(changes, frames, policy, |bounds| {
        bounds
            .iter()
            .map(|&(a, b)| direction_at(a + (b - a) / 2))
            .collect()
    })
}

/// The strokes between `changes`, one direction each from `directions`, planned.
fn plan_with(
    changes: &[usize],
    frames: usize,
    policy: &BowPolicy,
    directions: impl FnOnce(&[(usize, usize)]) -> Vec<BowDirection>,
) -> Result<BowPlan> {
    policy.validate()?;
    if frames == 0 {
        return Ok(BowPlan {
            strokes: Vec::new(),
            positions: Vec::new(),
        });
    }
    let bounds = stroke_bounds(changes, frames);
    let dirs = directions(&bounds);
    Ok(plan_strokes(&bounds, &dirs, frames, policy))
}

fn preferred_start(dir: BowDirection) -> f64 {
    match dir {
        BowDirection::Down => 0.0,
        BowDirection::Up => 1.0,
    }
}

/// The Viterbi of the module docs over `bounds` with one direction per stroke.
fn plan_strokes(
    bounds: &[(usize, usize)],
    dirs: &[BowDirection],
    frames: usize,
    policy: &BowPolicy,
) -> BowPlan {
    let m = policy.resolution;
    let grid = m as f64;
    let full = policy.full_bow_frames as f64;
    let k = bounds.len();
    let start_cost = |dir: BowDirection, j: usize| {
        policy.start_weight * (j as f64 / grid - preferred_start(dir)).abs()
    };
    let mut cost: Vec<f64> = (0..=m).map(|j| start_cost(dirs[0], j)).collect();
    let mut next = vec![f64::INFINITY; m + 1];
    let mut back = vec![0u32; k * (m + 1)];
    // For a retake before stroke i: where stroke i − 1 ended (the cheapest end).
    let mut reset_end: Vec<Option<usize>> = vec![None; k];
    let mut desired = Vec::with_capacity(k);
    for (i, &(a, b)) in bounds.iter().enumerate() {
        let dir = dirs[i];
        if i > 0 && dirs[i - 1] == dir {
            let (best, best_cost) =
                cost.iter()
                    .copied()
                    .enumerate()
                    .fold(
                        (0, f64::INFINITY),
                        |acc, (j, c)| if c < acc.1 { (j, c) } else { acc },
                    );
            reset_end[i] = Some(best);
            for (j, c) in cost.iter_mut().enumerate() {
                *c = best_cost + start_cost(dir, j);
            }
        }
        let n = b - a;
        let target = policy.desired_travel(n);
        desired.push(target);
        let max_travel = (policy.max_speed_factor * n as f64 / full)
            .max(target)
            .min(1.0);
        let max_steps = (max_travel * grid).floor() as usize;
        let weight = 1.0 / target.max(1e-9);
        next.fill(f64::INFINITY);
        let row = &mut back[i * (m + 1)..(i + 1) * (m + 1)];
        for (j, &c) in cost.iter().enumerate() {
            if !c.is_finite() {
                continue;
            }
            for steps in 0..=max_steps {
                let to = match dir {
                    BowDirection::Down if j + steps <= m => j + steps,
                    BowDirection::Up if steps <= j => j - steps,
                    _ => break,
                };
                let dt = steps as f64 / grid - target;
                let total = c + weight * dt * dt;
                if total < next[to] {
                    next[to] = total;
                    row[to] = j as u32;
                }
            }
        }
        std::mem::swap(&mut cost, &mut next);
    }
    // Backtrack from the cheapest end position.
    let mut end = 0;
    for (j, &c) in cost.iter().enumerate() {
        if c < cost[end] {
            end = j;
        }
    }
    let mut starts = vec![0usize; k];
    let mut ends = vec![0usize; k];
    ends[k - 1] = end;
    for i in (0..k).rev() {
        starts[i] = back[i * (m + 1) + ends[i]] as usize;
        if i > 0 {
            ends[i - 1] = reset_end[i].unwrap_or(starts[i]);
        }
    }
    let strokes: Vec<PlannedStroke> = bounds
        .iter()
        .enumerate()
        .map(|(i, &(a, b))| PlannedStroke {
            start_frame: a,
            end_frame: b,
            direction: dirs[i],
            start_position: starts[i] as f64 / grid,
            end_position: ends[i] as f64 / grid,
            desired_travel: desired[i],
        })
        .collect();
    let positions = sample_strokes(&strokes, frames, policy);
    BowPlan { strokes, positions }
}

/// The original pseudo-code taken literally (start at the frog, travel the desired amount,
/// reverse, no look-ahead): its positions may leave [0, 1]. Kept to measure the planner
/// against (see [`crate::metrics::bow_range_violations`]).
pub fn plan_naive(changes: &[usize], frames: usize, policy: &BowPolicy) -> Result<BowPlan> {
    policy.validate()?;
    let mut strokes = Vec::new();
    let mut pos = 0.0;
    let mut dir = BowDirection::Down;
    for (a, b) in stroke_bounds(changes, frames) {
        let travel = policy.desired_travel(b - a);
        let end = pos + dir.sign() * travel;
        strokes.push(PlannedStroke {
            start_frame: a,
            end_frame: b,
            direction: dir,
            start_position: pos,
            end_position: end,
            desired_travel: travel,
        });
        pos = end;
        dir = dir.reversed();
    }
    let positions = if frames == 0 {
        Vec::new()
    } else {
        sample_strokes(&strokes, frames, policy)
    };
    Ok(BowPlan { strokes, positions })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_rule_travel() {
        let p = BowPolicy::default();
        assert_eq!(p.desired_travel(14), 0.5);
        assert_eq!(p.desired_travel(7), 0.25);
        assert_eq!(p.desired_travel(15), 1.0);
        assert_eq!(p.desired_travel(200), 1.0);
    }

    #[test]
    fn a_long_first_stroke_is_a_full_down_bow_from_the_frog() {
        let plan = plan_bow(&[60], 120, &[], &BowPolicy::default()).unwrap();
        let s = plan.strokes();
        assert_eq!(s[0].direction, BowDirection::Down);
        assert_eq!((s[0].start_position, s[0].end_position), (0.0, 1.0));
        assert_eq!((s[1].start_position, s[1].end_position), (1.0, 0.0));
    }

    #[test]
    fn the_naive_rule_drifts_out_of_the_bow() {
        // long down, short up, long down …: the literal rule runs past the tip.
        let changes: Vec<usize> = (1..12)
            .map(|i| i * 25 - if i % 2 == 0 { 20 } else { 0 })
            .collect();
        let naive = plan_naive(&changes, 300, &BowPolicy::default()).unwrap();
        assert!(naive.positions().iter().any(|&p| !(0.0..=1.0).contains(&p)));
        let planned = plan_bow(&changes, 300, &[], &BowPolicy::default()).unwrap();
        assert!(planned
            .positions()
            .iter()
            .all(|&p| (0.0..=1.0).contains(&p)));
    }

    #[test]
    fn downbeats_choose_the_first_direction() {
        // Strokes start at 0, 30, 60, 90: downbeats at 30 and 90 are odd strokes → up first.
        let plan = plan_bow(&[30, 60, 90], 120, &[30.0, 90.0], &BowPolicy::default()).unwrap();
        assert_eq!(plan.strokes()[0].direction, BowDirection::Up);
        assert_eq!(plan.strokes()[1].direction, BowDirection::Down);
        let plain = plan_bow(&[30, 60, 90], 120, &[0.0, 60.0], &BowPolicy::default()).unwrap();
        assert_eq!(plain.strokes()[0].direction, BowDirection::Down);
    }

    #[test]
    fn bad_policy_and_degenerate_input() {
        let bad = BowPolicy {
            full_bow_frames: 0,
            ..BowPolicy::default()
        };
        assert!(plan_bow(&[], 10, &[], &bad).is_err());
        assert!(plan_bow(&[], 0, &[], &BowPolicy::default())
            .unwrap()
            .positions()
            .is_empty());
        let one = plan_bow(&[0, 5, 5, 99], 10, &[], &BowPolicy::default()).unwrap();
        assert_eq!(one.change_frames(), vec![5]);
        assert_eq!(
            change_frames(&[0.0, 0.1, 0.1, 0.2, 5.0], 30.0, 30),
            vec![3, 6]
        );
    }
}
