//! The ten joints the product animates, and their places in OpenPose's layouts.

use serde::{Deserialize, Serialize};

/// A joint of the violinist's skeleton (SPEC §3). The right arm is the bowing arm.
///
/// The order of [`Joint::ALL`] is the order of joints in every [`crate::Motion`] and file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Joint {
    /// Nose (stands in for the head).
    Nose,
    /// Neck (base of the neck, between the shoulders).
    Neck,
    /// Right shoulder.
    #[serde(rename = "r_shoulder")]
    RShoulder,
    /// Right elbow.
    #[serde(rename = "r_elbow")]
    RElbow,
    /// Right wrist (the bow hand).
    #[serde(rename = "r_wrist")]
    RWrist,
    /// Left shoulder.
    #[serde(rename = "l_shoulder")]
    LShoulder,
    /// Left elbow.
    #[serde(rename = "l_elbow")]
    LElbow,
    /// Left wrist (the fingering hand).
    #[serde(rename = "l_wrist")]
    LWrist,
    /// Right hip.
    #[serde(rename = "r_hip")]
    RHip,
    /// Left hip.
    #[serde(rename = "l_hip")]
    LHip,
}

/// Number of joints in [`Joint::ALL`].
pub const JOINT_COUNT: usize = 10;

/// Which OpenPose body model a keypoint array follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum PoseLayout {
    /// COCO, 18 keypoints.
    Coco18,
    /// BODY_25, 25 keypoints (OpenPose's default).
    Body25,
}

impl PoseLayout {
    /// Number of keypoints in this layout.
    pub fn keypoint_count(self) -> usize {
        match self {
            PoseLayout::Coco18 => 18,
            PoseLayout::Body25 => 25,
        }
    }

    /// The layout with this many keypoints, if any.
    pub fn from_keypoint_count(n: usize) -> Option<Self> {
        match n {
            18 => Some(PoseLayout::Coco18),
            25 => Some(PoseLayout::Body25),
            _ => None,
        }
    }
}

impl Joint {
    /// All joints, in the product's order.
    pub const ALL: [Joint; JOINT_COUNT] = [
        Joint::Nose,
        Joint::Neck,
        Joint::RShoulder,
        Joint::RElbow,
        Joint::RWrist,
        Joint::LShoulder,
        Joint::LElbow,
        Joint::LWrist,
        Joint::RHip,
        Joint::LHip,
    ];

    /// Index in [`Joint::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// The stable name used in files (`"r_wrist"`, …).
    ///
    /// ```
    /// assert_eq!(skeleton::Joint::RWrist.name(), "r_wrist");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Joint::Nose => "nose",
            Joint::Neck => "neck",
            Joint::RShoulder => "r_shoulder",
            Joint::RElbow => "r_elbow",
            Joint::RWrist => "r_wrist",
            Joint::LShoulder => "l_shoulder",
            Joint::LElbow => "l_elbow",
            Joint::LWrist => "l_wrist",
            Joint::RHip => "r_hip",
            Joint::LHip => "l_hip",
        }
    }

    /// The joint with this file name.
    pub fn from_name(name: &str) -> Option<Self> {
        Joint::ALL.into_iter().find(|j| j.name() == name)
    }

    /// Index of this joint in an OpenPose keypoint array of `layout`.
    ///
    /// ```
    /// use skeleton::{Joint, PoseLayout};
    /// assert_eq!(Joint::RHip.openpose_index(PoseLayout::Body25), 9);
    /// assert_eq!(Joint::RHip.openpose_index(PoseLayout::Coco18), 8);
    /// ```
    pub fn openpose_index(self, layout: PoseLayout) -> usize {
        // Both layouts share indices 0..=7 (nose, neck, right arm, left arm).
        match (self, layout) {
            (Joint::RHip, PoseLayout::Coco18) => 8,
            (Joint::LHip, PoseLayout::Coco18) => 11,
            (Joint::RHip, PoseLayout::Body25) => 9,
            (Joint::LHip, PoseLayout::Body25) => 12,
            (j, _) => j.index(),
        }
    }

    /// The joint at `index` of an OpenPose keypoint array of `layout`, if it is one of ours.
    pub fn from_openpose_index(index: usize, layout: PoseLayout) -> Option<Self> {
        Joint::ALL
            .into_iter()
            .find(|j| j.openpose_index(layout) == index)
    }
}

/// The bones drawn and measured: pairs of joints whose distance is constant on a real body.
pub const BONES: [(Joint, Joint); 10] = [
    (Joint::Neck, Joint::Nose),
    (Joint::Neck, Joint::RShoulder),
    (Joint::RShoulder, Joint::RElbow),
    (Joint::RElbow, Joint::RWrist),
    (Joint::Neck, Joint::LShoulder),
    (Joint::LShoulder, Joint::LElbow),
    (Joint::LElbow, Joint::LWrist),
    (Joint::Neck, Joint::RHip),
    (Joint::Neck, Joint::LHip),
    (Joint::RHip, Joint::LHip),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_serde_uses_them() {
        for j in Joint::ALL {
            assert_eq!(Joint::from_name(j.name()), Some(j));
            assert_eq!(
                serde_json::to_string(&j).unwrap(),
                format!("\"{}\"", j.name())
            );
        }
    }

    #[test]
    fn openpose_maps_are_inverse() {
        for layout in [PoseLayout::Coco18, PoseLayout::Body25] {
            for j in Joint::ALL {
                let i = j.openpose_index(layout);
                assert!(i < layout.keypoint_count());
                assert_eq!(Joint::from_openpose_index(i, layout), Some(j));
            }
        }
        // COCO-18: 8 = RHip, 11 = LHip; BODY_25: 8 = MidHip (not ours).
        assert_eq!(Joint::from_openpose_index(8, PoseLayout::Body25), None);
    }
}
