//! OpenPose's 21-point hand model: the wrist and four points along each finger.

/// A finger, thumb first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Finger {
    /// Thumb.
    Thumb,
    /// Index finger (violinists' finger 1).
    Index,
    /// Middle finger (2).
    Middle,
    /// Ring finger (3).
    Ring,
    /// Little finger (4).
    Pinky,
}

impl Finger {
    /// All fingers in OpenPose order.
    pub const ALL: [Finger; 5] = [
        Finger::Thumb,
        Finger::Index,
        Finger::Middle,
        Finger::Ring,
        Finger::Pinky,
    ];

    /// The name used in point names.
    pub fn name(self) -> &'static str {
        match self {
            Finger::Thumb => "thumb",
            Finger::Index => "index",
            Finger::Middle => "middle",
            Finger::Ring => "ring",
            Finger::Pinky => "pinky",
        }
    }

    /// Index of this finger's point `k` (1 = base knuckle … 4 = tip) in a hand track.
    ///
    /// ```
    /// use skeleton::Finger;
    /// assert_eq!(Finger::Thumb.point(1), 1);
    /// assert_eq!(Finger::Pinky.point(4), 20);
    /// ```
    pub fn point(self, k: usize) -> usize {
        1 + 4 * (self as usize) + k.clamp(1, 4) - 1
    }

    /// The fingertip's index in a hand track.
    pub fn tip(self) -> usize {
        self.point(4)
    }
}

/// Number of hand points.
pub const HAND_POINT_COUNT: usize = 21;

/// The names of the 21 hand points, in OpenPose order: `wrist`, `thumb_1` … `thumb_4`,
/// `index_1` … `pinky_4` (1 = base knuckle, 4 = tip).
pub const HAND_POINT_NAMES: [&str; HAND_POINT_COUNT] = [
    "wrist", "thumb_1", "thumb_2", "thumb_3", "thumb_4", "index_1", "index_2", "index_3",
    "index_4", "middle_1", "middle_2", "middle_3", "middle_4", "ring_1", "ring_2", "ring_3",
    "ring_4", "pinky_1", "pinky_2", "pinky_3", "pinky_4",
];

/// The 20 bones of a hand as index pairs: wrist → each base knuckle, then along each finger.
pub const HAND_BONES: [(usize, usize); 20] = {
    let mut out = [(0, 0); 20];
    let mut f = 0;
    while f < 5 {
        let base = 1 + 4 * f;
        out[4 * f] = (0, base);
        out[4 * f + 1] = (base, base + 1);
        out[4 * f + 2] = (base + 1, base + 2);
        out[4 * f + 3] = (base + 2, base + 3);
        f += 1;
    }
    out
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_bones_follow_the_finger_chains() {
        for f in Finger::ALL {
            for k in 1..=4 {
                assert_eq!(HAND_POINT_NAMES[f.point(k)], format!("{}_{k}", f.name()));
            }
        }
        assert_eq!(HAND_BONES[0], (0, 1));
        assert_eq!(HAND_BONES[19], (19, 20));
        assert!(HAND_BONES
            .iter()
            .all(|&(a, b)| a < b && b < HAND_POINT_COUNT));
    }
}
