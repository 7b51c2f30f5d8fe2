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
//! not swap them. The decisions form a chain from the first frame, so afterwards the
//! labelling that holds in the majority of frames is kept: when most frames of a pair were
//! swapped, the chain started on a swapped frame and every decision of that pair is inverted.

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

/// Swaps detected left/right joints back (see the module documentation). Returns the number
/// of joint-pair frames swapped.
pub fn fix_left_right_swaps(performer: &mut [Option<Detection>], threshold: f32) -> usize {
    let ok = |c: f32| c >= threshold && c > 0.0;
    let mut swapped_frames = 0;
    for (r, l) in PAIRS {
        let (r, l) = (r.index(), l.index());
        let mut last: [Option<[f32; 2]>; 2] = [None, None];
        let mut swap = vec![false; performer.len()];
        let mut known = 0usize;
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
                known += 1;
            }
        }
        let count = swap.iter().filter(|s| **s).count();
        let invert = 2 * count > known;
        for (t, d) in performer.iter_mut().enumerate() {
            let Some(d) = d else { continue };
            if !(ok(d.joints[r][2]) || ok(d.joints[l][2])) {
                continue;
            }
            if swap[t] != invert {
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
}
