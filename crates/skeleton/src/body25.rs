//! OpenPose's BODY_25 body model: the 25 points of a whole standing performer, their order,
//! names and bones, and how the ten core [`Joint`]s sit among them.

use crate::joint::Joint;

/// A point of OpenPose's BODY_25 model, in its order (the player's right is `R…`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BodyPoint {
    /// 0: nose.
    Nose,
    /// 1: neck (base of the neck).
    Neck,
    /// 2: right shoulder.
    RShoulder,
    /// 3: right elbow.
    RElbow,
    /// 4: right wrist.
    RWrist,
    /// 5: left shoulder.
    LShoulder,
    /// 6: left elbow.
    LElbow,
    /// 7: left wrist.
    LWrist,
    /// 8: centre of the hips.
    MidHip,
    /// 9: right hip.
    RHip,
    /// 10: right knee.
    RKnee,
    /// 11: right ankle.
    RAnkle,
    /// 12: left hip.
    LHip,
    /// 13: left knee.
    LKnee,
    /// 14: left ankle.
    LAnkle,
    /// 15: right eye.
    REye,
    /// 16: left eye.
    LEye,
    /// 17: right ear.
    REar,
    /// 18: left ear.
    LEar,
    /// 19: left big toe.
    LBigToe,
    /// 20: left small toe.
    LSmallToe,
    /// 21: left heel.
    LHeel,
    /// 22: right big toe.
    RBigToe,
    /// 23: right small toe.
    RSmallToe,
    /// 24: right heel.
    RHeel,
}

/// Number of BODY_25 points.
pub const BODY25_COUNT: usize = 25;

impl BodyPoint {
    /// All points in BODY_25 order.
    pub const ALL: [BodyPoint; BODY25_COUNT] = [
        BodyPoint::Nose,
        BodyPoint::Neck,
        BodyPoint::RShoulder,
        BodyPoint::RElbow,
        BodyPoint::RWrist,
        BodyPoint::LShoulder,
        BodyPoint::LElbow,
        BodyPoint::LWrist,
        BodyPoint::MidHip,
        BodyPoint::RHip,
        BodyPoint::RKnee,
        BodyPoint::RAnkle,
        BodyPoint::LHip,
        BodyPoint::LKnee,
        BodyPoint::LAnkle,
        BodyPoint::REye,
        BodyPoint::LEye,
        BodyPoint::REar,
        BodyPoint::LEar,
        BodyPoint::LBigToe,
        BodyPoint::LSmallToe,
        BodyPoint::LHeel,
        BodyPoint::RBigToe,
        BodyPoint::RSmallToe,
        BodyPoint::RHeel,
    ];

    /// Index in BODY_25 (and in a performer's body track).
    pub fn index(self) -> usize {
        self as usize
    }

    /// The stable name used in files (the core joints keep their names: `"r_wrist"`, …).
    ///
    /// ```
    /// assert_eq!(skeleton::BodyPoint::LBigToe.name(), "l_big_toe");
    /// assert_eq!(skeleton::BodyPoint::RWrist.name(), "r_wrist");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            BodyPoint::Nose => "nose",
            BodyPoint::Neck => "neck",
            BodyPoint::RShoulder => "r_shoulder",
            BodyPoint::RElbow => "r_elbow",
            BodyPoint::RWrist => "r_wrist",
            BodyPoint::LShoulder => "l_shoulder",
            BodyPoint::LElbow => "l_elbow",
            BodyPoint::LWrist => "l_wrist",
            BodyPoint::MidHip => "mid_hip",
            BodyPoint::RHip => "r_hip",
            BodyPoint::RKnee => "r_knee",
            BodyPoint::RAnkle => "r_ankle",
            BodyPoint::LHip => "l_hip",
            BodyPoint::LKnee => "l_knee",
            BodyPoint::LAnkle => "l_ankle",
            BodyPoint::REye => "r_eye",
            BodyPoint::LEye => "l_eye",
            BodyPoint::REar => "r_ear",
            BodyPoint::LEar => "l_ear",
            BodyPoint::LBigToe => "l_big_toe",
            BodyPoint::LSmallToe => "l_small_toe",
            BodyPoint::LHeel => "l_heel",
            BodyPoint::RBigToe => "r_big_toe",
            BodyPoint::RSmallToe => "r_small_toe",
            BodyPoint::RHeel => "r_heel",
        }
    }

    /// The BODY_25 point that is the core joint `joint` (same place, same coordinates).
    ///
    /// ```
    /// use skeleton::{BodyPoint, Joint};
    /// assert_eq!(BodyPoint::of_joint(Joint::LHip), BodyPoint::LHip);
    /// assert_eq!(BodyPoint::of_joint(Joint::LHip).index(), 12);
    /// ```
    pub fn of_joint(joint: Joint) -> BodyPoint {
        match joint {
            Joint::Nose => BodyPoint::Nose,
            Joint::Neck => BodyPoint::Neck,
            Joint::RShoulder => BodyPoint::RShoulder,
            Joint::RElbow => BodyPoint::RElbow,
            Joint::RWrist => BodyPoint::RWrist,
            Joint::LShoulder => BodyPoint::LShoulder,
            Joint::LElbow => BodyPoint::LElbow,
            Joint::LWrist => BodyPoint::LWrist,
            Joint::RHip => BodyPoint::RHip,
            Joint::LHip => BodyPoint::LHip,
        }
    }

    /// Index of this point in OpenPose's COCO-18 model, when it has one (no mid-hip,
    /// toes or heels there).
    pub fn coco18_index(self) -> Option<usize> {
        let i = self.index();
        match self {
            BodyPoint::MidHip => None,
            _ if i <= 7 => Some(i),
            BodyPoint::RHip | BodyPoint::RKnee | BodyPoint::RAnkle => Some(i - 1),
            BodyPoint::LHip | BodyPoint::LKnee | BodyPoint::LAnkle => Some(i - 1),
            BodyPoint::REye | BodyPoint::LEye | BodyPoint::REar | BodyPoint::LEar => Some(i - 1),
            _ => None,
        }
    }
}

/// The bones of BODY_25 as OpenPose draws them (all rigid on a real body).
pub const BODY25_BONES: [(BodyPoint, BodyPoint); 24] = [
    (BodyPoint::Neck, BodyPoint::MidHip),
    (BodyPoint::Neck, BodyPoint::RShoulder),
    (BodyPoint::Neck, BodyPoint::LShoulder),
    (BodyPoint::RShoulder, BodyPoint::RElbow),
    (BodyPoint::RElbow, BodyPoint::RWrist),
    (BodyPoint::LShoulder, BodyPoint::LElbow),
    (BodyPoint::LElbow, BodyPoint::LWrist),
    (BodyPoint::MidHip, BodyPoint::RHip),
    (BodyPoint::RHip, BodyPoint::RKnee),
    (BodyPoint::RKnee, BodyPoint::RAnkle),
    (BodyPoint::MidHip, BodyPoint::LHip),
    (BodyPoint::LHip, BodyPoint::LKnee),
    (BodyPoint::LKnee, BodyPoint::LAnkle),
    (BodyPoint::Neck, BodyPoint::Nose),
    (BodyPoint::Nose, BodyPoint::REye),
    (BodyPoint::REye, BodyPoint::REar),
    (BodyPoint::Nose, BodyPoint::LEye),
    (BodyPoint::LEye, BodyPoint::LEar),
    (BodyPoint::LAnkle, BodyPoint::LBigToe),
    (BodyPoint::LBigToe, BodyPoint::LSmallToe),
    (BodyPoint::LAnkle, BodyPoint::LHeel),
    (BodyPoint::RAnkle, BodyPoint::RBigToe),
    (BodyPoint::RBigToe, BodyPoint::RSmallToe),
    (BodyPoint::RAnkle, BodyPoint::RHeel),
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::joint::PoseLayout;

    #[test]
    fn core_joints_sit_at_their_openpose_indices() {
        for j in Joint::ALL {
            let p = BodyPoint::of_joint(j);
            assert_eq!(p.index(), j.openpose_index(PoseLayout::Body25));
            assert_eq!(p.coco18_index(), Some(j.openpose_index(PoseLayout::Coco18)));
            assert_eq!(p.name(), j.name());
        }
        for (i, p) in BodyPoint::ALL.iter().enumerate() {
            assert_eq!(p.index(), i);
        }
        assert_eq!(BodyPoint::LEar.coco18_index(), Some(17));
        assert_eq!(BodyPoint::LAnkle.coco18_index(), Some(13));
        assert_eq!(BodyPoint::RHeel.coco18_index(), None);
    }
}
