//! Undoing left/right swaps of the pose estimator.
//!
//! Pose estimators sometimes label a person's left joints as right and the right as left for
//! a few frames (most often in side views). A swapped wrist makes the bowing wrist's track
//! jump to the other hand and back, which the labelling rule would read as bow changes.
//!
//! Each left/right pair (shoulders, elbows, wrists, hips) is followed on its own: in every
//! frame where the pair's joints are confident, the pair is swapped when the swapped
//! assignment lies less than half as far from the pair's last known positions as the given
//! one (both joints, or the one that is confident), so that jitter on two nearby joints does
//! not swap them. The decisions form a chain from the first frame: a swap whose start was
//! missed (the joints overlapped) but whose end was seen would invert the rest of the clip.
//! Estimators swap only briefly, so the chain is cut into runs of equal decisions: a run
//! longer than `max_swap_frames` is the true labelling whatever the chain says, and a short
//! run is swapped back only when it differs from the long run before it (or, at the start,
//! after it). A wrong decision thus costs at most the frames of one swap. Without any long
//! run, the labelling that holds in the majority of frames is kept.

use skeleton::Joint;

use crate::read::Detection;

/// The left/right pairs, `(right, left)`.
const PAIRS: [(Joint, Joint); 4] = [
    (Joint::RShoulder, Joint::LShoulder),
    (Joint::RElbow, Joint::LElbow),
    (Joint::RWrist, Joint::LWrist),
    (Joint::RHip, Joint::LHip),
];

/// A pair is swapped only when the swapped assignment is at most this fraction of the given
/// one's distance: jitter on two nearby joints (the wrists in a side view) must not swap them.
const SWAP_MARGIN: f32 = 0.5;

fn dist(a: [f32; 2], b: [f32; 2]) -> f32 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Longest left/right swap of a pose estimator, seconds (see the module documentation).
pub const MAX_SWAP_S: f64 = 1.0;

/// [`fix_left_right_swaps_within`] with swaps of at most 30 frames (1 s at 30 fps).
pub fn fix_left_right_swaps(performer: &mut [Option<Detection>], threshold: f32) -> usize {
    fix_left_right_swaps_within(performer, threshold, 30)
}

/// Per known frame, whether to swap it, given the chain's decisions `chain` on those frames
/// (at `frames`, increasing): runs spanning at least `max_swap_frames` frames are the true
/// labelling; shorter runs are swapped when they differ from the long run before them (the
/// one after them at the start); without long runs, the minority is swapped.
fn final_swaps(chain: &[bool], frames: &[usize], max_swap_frames: usize) -> Vec<bool> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for i in 0..chain.len() {
        match runs.last_mut() {
            Some(run) if chain[run.0] == chain[i] => run.1 = i,
            _ => runs.push((i, i)),
        }
    }
    let long = |&(a, b): &(usize, usize)| frames[b] - frames[a] + 1 >= max_swap_frames;
    let Some(first_long) = runs.iter().find(|r| long(r)) else {
        let count = chain.iter().filter(|s| **s).count();
        let invert = 2 * count > chain.len();
        return chain.iter().map(|&s| s != invert).collect();
    };
    let mut reference = chain[first_long.0];
    let mut out = vec![false; chain.len()];
    for run in &runs {
        if long(run) {
            reference = chain[run.0];
        }
        for slot in &mut out[run.0..=run.1] {
            *slot = chain[run.0] != reference;
        }
    }
    out
}

/// Swaps detected left/right joints back (see the module documentation); an estimator's swap
/// lasts at most `max_swap_frames`. Returns the number of joint-pair frames swapped.
pub fn fix_left_right_swaps_within(
    performer: &mut [Option<Detection>],
    threshold: f32,
    max_swap_frames: usize,
) -> usize {
    let ok = |c: f32| c >= threshold && c > 0.0;
    let mut swapped_frames = 0;
    for (r, l) in PAIRS {
        let (r, l) = (r.index(), l.index());
        let mut last: [Option<[f32; 2]>; 2] = [None, None];
        let mut swap = vec![false; performer.len()];
        let mut known: Vec<usize> = Vec::new();
        for (t, d) in performer.iter().enumerate() {
            let Some(d) = d else { continue };
            let (pr, pl) = (d.joints[r], d.joints[l]);
            let (cr, cl) = (ok(pr[2]), ok(pl[2]));
            let (xr, xl) = ([pr[0], pr[1]], [pl[0], pl[1]]);
            let s = match (cr, cl, last) {
                (true, true, [Some(lr), Some(ll)]) => {
                    dist(xr, ll) + dist(xl, lr) < SWAP_MARGIN * (dist(xr, lr) + dist(xl, ll))
                }
                (true, false, [Some(lr), Some(ll)]) => dist(xr, ll) < SWAP_MARGIN * dist(xr, lr),
                (false, true, [Some(lr), Some(ll)]) => dist(xl, lr) < SWAP_MARGIN * dist(xl, ll),
                _ => false,
            };
            swap[t] = s;
            let (nr, nl) = if s { (xl, xr) } else { (xr, xl) };
            let (okr, okl) = if s { (cl, cr) } else { (cr, cl) };
            if okr {
                last[0] = Some(nr);
            }
            if okl {
                last[1] = Some(nl);
            }
            if cr || cl {
                known.push(t);
            }
        }
        let chain: Vec<bool> = known.iter().map(|&t| swap[t]).collect();
        let fixed = final_swaps(&chain, &known, max_swap_frames.max(1));
        for (&t, _) in known.iter().zip(fixed).filter(|(_, f)| *f) {
            if let Some(d) = performer.get_mut(t).and_then(Option::as_mut) {
                d.joints.swap(r, l);
                swapped_frames += 1;
            }
        }
    }
    swapped_frames
}

#[cfg(test)]
mod tests {
    use super::*;
    use skeleton::JOINT_COUNT;

    fn person(t: usize) -> Detection {
        let mut joints = [[0.0f32, 0.0, 0.9]; JOINT_COUNT];
        for j in Joint::ALL {
            let side = match j {
                Joint::RShoulder | Joint::RElbow | Joint::RWrist | Joint::RHip => -1.0,
                Joint::LShoulder | Joint::LElbow | Joint::LWrist | Joint::LHip => 1.0,
                _ => 0.0,
            };
            joints[j.index()] = [
                500.0 + 100.0 * side + t as f32,
                300.0 + j.index() as f32,
                0.9,
            ];
        }
        Detection { joints }
    }

    #[test]
    fn short_swaps_are_undone_and_the_majority_labelling_kept() {
        let truth: Vec<Option<Detection>> = (0..50).map(|t| Some(person(t))).collect();
        let mut seen = truth.clone();
        for d in seen.iter_mut().take(20).skip(10).flatten() {
            d.joints.swap(Joint::RWrist.index(), Joint::LWrist.index());
        }
        assert_eq!(fix_left_right_swaps(&mut seen, 0.05), 10);
        assert_eq!(seen, truth);
        // Swapped from the first frame for 5 frames: the later majority wins.
        let mut seen = truth.clone();
        for d in seen.iter_mut().take(5).flatten() {
            for (r, l) in PAIRS {
                d.joints.swap(r.index(), l.index());
            }
        }
        assert_eq!(fix_left_right_swaps(&mut seen, 0.05), 20);
        assert_eq!(seen, truth);
    }

    #[test]
    fn a_swap_whose_start_was_missed_costs_only_its_own_frames() {
        // Chain: the swap of frames 40..44 was missed at its start but its end was seen,
        // so the chain says "swapped" from frame 44 to the end.
        let frames: Vec<usize> = (0..100).collect();
        let chain: Vec<bool> = frames.iter().map(|&t| t >= 44).collect();
        assert!(final_swaps(&chain, &frames, 30).iter().all(|s| !s));
        // A short swap inside long runs is undone; the long runs are kept.
        let chain: Vec<bool> = frames.iter().map(|&t| (40..45).contains(&t)).collect();
        let fixed = final_swaps(&chain, &frames, 30);
        assert_eq!(fixed, chain);
        // No long run: the majority labelling is kept.
        let chain = [true, true, false];
        assert_eq!(
            final_swaps(&chain, &[0, 1, 2], 30),
            vec![false, false, true]
        );
    }
}
