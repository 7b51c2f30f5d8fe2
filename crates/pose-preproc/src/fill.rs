//! Filling missing joints: linear interpolation over short gaps, holding over long ones.

use ndarray::Array3;
use skeleton::{Joint, JOINT_COUNT};

use crate::quality::Gap;
use crate::read::Detection;

/// The filled 2-D track and what filling did.
#[derive(Debug, Clone, PartialEq)]
pub struct Filled {
    /// `(T, 10, 2)`, pixels, no NaN.
    pub frames: Array3<f32>,
    /// Joint-frames filled by interpolation.
    pub filled_joint_frames: usize,
    /// Joint-frames held at the nearest valid value.
    pub held_joint_frames: usize,
    /// Gaps longer than `max_gap_frames`, in joint order then time.
    pub long_gaps: Vec<Gap>,
}

/// Fills the performer's track. A joint is missing in a frame without a performer, or when
/// its confidence is below `threshold`. Interior gaps of at most `max_gap_frames` are
/// interpolated linearly between the valid frames around them; longer interior gaps hold the
/// last valid value; gaps at the clip's start (end) hold the first (last) valid value. Gaps
/// longer than `max_gap_frames` are listed.
///
/// Fails with the joint that is never valid (it cannot be filled).
pub fn fill_gaps(
    performer: &[Option<&Detection>],
    threshold: f32,
    max_gap_frames: usize,
) -> Result<Filled, Joint> {
    let t_len = performer.len();
    let mut frames = Array3::<f32>::zeros((t_len, JOINT_COUNT, 2));
    let mut out = Filled {
        frames: Array3::zeros((0, JOINT_COUNT, 2)),
        filled_joint_frames: 0,
        held_joint_frames: 0,
        long_gaps: Vec::new(),
    };
    let mut valid = vec![false; t_len];
    for joint in Joint::ALL {
        let j = joint.index();
        for (t, p) in performer.iter().enumerate() {
            let point = p
                .map(|d| d.joints[j])
                .filter(|q| q[2] >= threshold && q[2] > 0.0);
            valid[t] = point.is_some();
            if let Some(q) = point {
                frames[[t, j, 0]] = q[0];
                frames[[t, j, 1]] = q[1];
            }
        }
        if !valid.iter().any(|v| *v) {
            return Err(joint);
        }
        let mut t = 0;
        while t < t_len {
            if valid[t] {
                t += 1;
                continue;
            }
            let start = t;
            while t < t_len && !valid[t] {
                t += 1;
            }
            let len = t - start;
            let before = start.checked_sub(1);
            let after = (t < t_len).then_some(t);
            if len > max_gap_frames {
                out.long_gaps.push(Gap {
                    joint,
                    start_frame: start,
                    len,
                });
            }
            match (before, after) {
                (Some(b), Some(a)) if len <= max_gap_frames => {
                    for c in 0..2 {
                        let (y0, y1) = (frames[[b, j, c]], frames[[a, j, c]]);
                        for k in start..a {
                            let w = (k - b) as f32 / (a - b) as f32;
                            frames[[k, j, c]] = y0 + w * (y1 - y0);
                        }
                    }
                    out.filled_joint_frames += len;
                }
                _ => {
                    // The joint has a valid frame, so one side exists.
                    if let Some(hold) = before.or(after) {
                        for k in start..t {
                            for c in 0..2 {
                                frames[[k, j, c]] = frames[[hold, j, c]];
                            }
                        }
                        out.held_joint_frames += len;
                    }
                }
            }
        }
    }
    out.frames = frames;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn det(x: f32, c: f32) -> Detection {
        Detection {
            joints: [[x, 2.0 * x, c]; JOINT_COUNT],
        }
    }

    #[test]
    fn short_gaps_interpolate_long_gaps_hold_and_are_listed() {
        // x: 0 1 _ _ 4 5 _ _ _ _ _ 11 _
        let dets: Vec<Detection> = (0..13)
            .map(|t| {
                det(
                    t as f32,
                    if [2, 3, 6, 7, 8, 9, 10, 12].contains(&t) {
                        0.0
                    } else {
                        0.9
                    },
                )
            })
            .collect();
        let refs: Vec<Option<&Detection>> = dets.iter().map(Some).collect();
        let f = fill_gaps(&refs, 0.05, 3).unwrap();
        let x: Vec<f32> = (0..13).map(|t| f.frames[[t, 4, 0]]).collect();
        assert_eq!(
            x,
            vec![0., 1., 2., 3., 4., 5., 5., 5., 5., 5., 5., 11., 11.]
        );
        assert_eq!(f.frames[[3, 4, 1]], 6.0);
        assert_eq!(f.filled_joint_frames, 2 * JOINT_COUNT);
        assert_eq!(f.held_joint_frames, 6 * JOINT_COUNT);
        assert_eq!(f.long_gaps.len(), JOINT_COUNT);
        assert_eq!(
            f.long_gaps[0],
            Gap {
                joint: Joint::Nose,
                start_frame: 6,
                len: 5
            }
        );
    }

    #[test]
    fn leading_gap_holds_first_value_and_missing_frames_count() {
        let d = det(7.0, 0.5);
        let refs = vec![None, None, Some(&d), Some(&d)];
        let f = fill_gaps(&refs, 0.05, 15).unwrap();
        assert_eq!(f.frames[[0, 0, 0]], 7.0);
        assert_eq!(f.held_joint_frames, 2 * JOINT_COUNT);
        assert!(f.long_gaps.is_empty());
    }

    #[test]
    fn never_detected_joint_is_an_error() {
        let mut d = det(1.0, 0.9);
        d.joints[Joint::LHip.index()][2] = 0.01;
        assert_eq!(fill_gaps(&[Some(&d)], 0.05, 15), Err(Joint::LHip));
    }
}
