//! The 3-D violinist: bone lengths of an adult, the violin and the bow as rigid objects, and
//! the pose for one frame's musical state.
//!
//! Frames: the **world** is metres with the origin on the floor between the feet, x to the
//! player's left, y up, z forward (the way the player faces). The **torso frame** has its
//! origin at the centre of the hips and turns with the torso's forward/back tilt, a rotation
//! about the line through both hips (so the hips never move and the neck–hip bones keep
//! their length). The violin is fixed in the torso frame (it rests on the left collarbone).

use skeleton::{InstrumentPoint, Joint, JOINT_COUNT};

use crate::geometry::{Mat3, Transform, Vec3};
use crate::ik::two_link;

/// The violin's place and shape (metres, degrees). It lies on the left collarbone with its
/// scroll pointing forward-left and slightly up, rolled so that the top faces the bow arm.
#[derive(Debug, Clone, PartialEq)]
pub struct ViolinGeometry {
    /// The end button (tail end, under the chin), in the torso frame.
    pub end_button: Vec3,
    /// Turn of the violin's axis from straight ahead towards the player's left.
    pub yaw_deg: f64,
    /// Rise of the axis above horizontal towards the scroll.
    pub pitch_deg: f64,
    /// Roll about the axis that turns the top towards the player's right (E side down).
    pub roll_deg: f64,
    /// End button → end of the scroll.
    pub length: f64,
    /// Length of the body.
    pub body_length: f64,
    /// End button → bridge.
    pub bridge_from_end: f64,
    /// Vibrating string length, bridge → nut.
    pub string_length: f64,
    /// Height of the middle strings above the top at the bridge.
    pub string_height: f64,
    /// Distance between neighbouring strings at the bridge.
    pub string_spacing: f64,
    /// Height of the middle strings above the top's plane at the nut (the fingerboard).
    pub nut_string_height: f64,
    /// Distance between neighbouring strings at the nut.
    pub nut_string_spacing: f64,
    /// Bow contact point's distance from the bridge towards the fingerboard.
    pub contact_from_bridge: f64,
    /// Elevation of the bow's tip above the top plate when playing G, D, A, E (degrees;
    /// the bridge's curve makes the bow tilt a little more for each higher string).
    pub string_angles_deg: [f64; 4],
}

impl Default for ViolinGeometry {
    fn default() -> Self {
        ViolinGeometry {
            end_button: Vec3::new(0.05, 0.46, 0.07),
            yaw_deg: 40.0,
            pitch_deg: 5.0,
            roll_deg: 25.0,
            length: 0.59,
            body_length: 0.356,
            bridge_from_end: 0.161,
            string_length: 0.328,
            string_height: 0.03,
            string_spacing: 0.0113,
            nut_string_height: 0.02,
            nut_string_spacing: 0.0055,
            contact_from_bridge: 0.025,
            string_angles_deg: [-12.0, -4.0, 4.0, 12.0],
        }
    }
}

/// The bow (metres): a rigid stick whose hair touches the string at a point that moves
/// along it with the bow position.
#[derive(Debug, Clone, PartialEq)]
pub struct BowGeometry {
    /// Frog end → tip.
    pub length: f64,
    /// Usable hair, from the frog-side contact point to the tip-side one.
    pub hair_length: f64,
    /// Frog → first usable contact point.
    pub frog_margin: f64,
    /// Turn of the bow within the strings' plane at the tip (degrees, growing linearly
    /// from 0 at the frog), bringing the frog back towards the body as players do when the
    /// arm runs out of reach.
    pub skew_at_tip_deg: f64,
}

impl Default for BowGeometry {
    fn default() -> Self {
        BowGeometry {
            length: 0.75,
            hair_length: 0.65,
            frog_margin: 0.04,
            skew_at_tip_deg: 15.0,
        }
    }
}

/// The violinist's body (an adult of about 1.75 m, metres) with violin and bow.
#[derive(Debug, Clone, PartialEq)]
pub struct Rig {
    /// Height of the hip joints above the floor (standing).
    pub hip_height: f64,
    /// Right hip ↔ left hip.
    pub hip_width: f64,
    /// Hip centre → neck (base of the neck).
    pub torso_length: f64,
    /// Right shoulder ↔ left shoulder.
    pub shoulder_width: f64,
    /// How far the shoulder joints sit below the neck.
    pub shoulder_drop: f64,
    /// Neck → nose.
    pub neck_length: f64,
    /// Shoulder → elbow.
    pub upper_arm: f64,
    /// Elbow → wrist.
    pub forearm: f64,
    /// Right wrist → the frog held in the fingers.
    pub hand_length: f64,
    /// Angle of the nose forward of straight up from the neck (degrees).
    pub nose_forward_deg: f64,
    /// Head turned towards the violin (left), degrees.
    pub head_turn_deg: f64,
    /// Head tilted towards the left shoulder onto the chin rest, degrees.
    pub head_tilt_deg: f64,
    /// Direction the right elbow bends towards, torso frame.
    pub right_elbow_pole: Vec3,
    /// Direction the left elbow bends towards, torso frame.
    pub left_elbow_pole: Vec3,
    /// The violin.
    pub violin: ViolinGeometry,
    /// The bow.
    pub bow: BowGeometry,
}

impl Default for Rig {
    fn default() -> Self {
        Rig {
            hip_height: 0.95,
            hip_width: 0.18,
            torso_length: 0.50,
            shoulder_width: 0.38,
            shoulder_drop: 0.03,
            neck_length: 0.21,
            upper_arm: 0.30,
            forearm: 0.27,
            hand_length: 0.10,
            nose_forward_deg: 25.0,
            head_turn_deg: 25.0,
            head_tilt_deg: 12.0,
            right_elbow_pole: Vec3::new(-0.8, -0.55, -0.25),
            left_elbow_pole: Vec3::new(-0.45, -1.0, 0.05),
            violin: ViolinGeometry::default(),
            bow: BowGeometry::default(),
        }
    }
}

/// The musical state of one frame, as the rig needs it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PoseInput {
    /// Torso tilt about the hip line, radians; positive leans forward.
    pub torso_pitch_rad: f64,
    /// Head nod relative to the torso, radians; positive nods forward.
    pub head_pitch_rad: f64,
    /// Bow position, 0 = frog … 1 = tip at the string.
    pub bow_position: f64,
    /// String being bowed as a continuous index: 0 = G, 1 = D, 2 = A, 3 = E.
    pub string_index: f64,
    /// Left hand's place along the neck, semitones from the nut
    /// ([`fingering::Fingering::hand_offset_semitones`]).
    pub hand_semitones: f64,
    /// Weight shift: the hips' sideways displacement, metres (+ towards the player's left).
    pub hip_shift_m: f64,
    /// Pelvis roll with the weight shift, radians (+ raises the left hip).
    pub hip_roll_rad: f64,
    /// Right-hand finger flexion, 0 (relaxed) … 1 (flexed, at a bow change).
    pub right_flex: f64,
}

/// One frame's 3-D pose, world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Joints in [`Joint::ALL`] order.
    pub joints: [Vec3; JOINT_COUNT],
    /// Instrument points in [`InstrumentPoint::ALL`] order.
    pub instrument: [Vec3; 4],
    /// `false` when a wrist could not reach its target (the rig is badly proportioned).
    pub reached: bool,
    /// The frames the pose was built in, for the hands, legs and instrument parts.
    pub parts: PoseParts,
}

/// The frames and anchor points of one pose (torso frame unless said otherwise), from which
/// the whole performer (hands, legs, head, violin and bow parts) is built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseParts {
    /// Torso frame → world.
    pub torso: Transform,
    /// Head rotation relative to the torso (about the neck).
    pub head: Mat3,
    /// Violin-local axes → torso frame (x across the strings towards G, y the top's
    /// normal, z along the strings towards the scroll).
    pub violin: Mat3,
    /// Where the bow's hair line (through the contact point) meets the frog end.
    pub hair_frog: Vec3,
    /// Unit direction from frog to tip.
    pub bow_dir: Vec3,
    /// Unit direction from the hair to the stick.
    pub stick_up: Vec3,
    /// Right wrist (IK result).
    pub r_wrist: Vec3,
    /// Left wrist (IK result).
    pub l_wrist: Vec3,
}

/// Height of the stick above the hair at the frog and at the tip, metres.
const STICK_AT_FROG: f64 = 0.018;
const STICK_AT_TIP: f64 = 0.008;
/// How much closer to the frog the right wrist comes at full finger flexion, metres.
const FLEX_PULL: f64 = 0.004;

/// Rotation taking violin-local axes (x: across the strings towards G, y: the top's normal,
/// z: along the strings towards the scroll) into the torso frame.
pub(crate) fn violin_rotation(v: &ViolinGeometry) -> Mat3 {
    Mat3::rot_y(v.yaw_deg.to_radians())
        * Mat3::rot_x(-v.pitch_deg.to_radians())
        * Mat3::rot_z(v.roll_deg.to_radians())
}

impl Rig {
    /// Hip centre in the world.
    pub fn hip_centre(&self) -> Vec3 {
        Vec3::new(0.0, self.hip_height, 0.0)
    }

    /// The bow's tip elevation (radians) for a continuous string index (0 = G … 3 = E).
    fn string_angle(&self, string_index: f64) -> f64 {
        let s = string_index.clamp(0.0, 3.0);
        let i = (s.floor() as usize).min(2);
        let t = s - i as f64;
        let a = &self.violin.string_angles_deg;
        (a[i] + (a[i + 1] - a[i]) * t).to_radians()
    }

    /// Distance from the nut to where a finger stops the string `semitones` above it.
    fn stop_distance(&self, semitones: f64) -> f64 {
        self.violin.string_length * (1.0 - (-semitones.max(0.0) / 12.0).exp2())
    }

    /// The 3-D pose for `input`. Bone lengths are exact by construction: the head turns
    /// about the neck, the torso about the hip line, and the arms come from two-link IK.
    pub fn pose(&self, input: &PoseInput) -> Pose {
        let v = &self.violin;
        let vrot = violin_rotation(v);
        let on_violin = |x: f64, y: f64, along: f64| v.end_button + vrot * Vec3::new(x, y, along);

        let neck = Vec3::new(0.0, self.torso_length, 0.0);
        let half_sw = self.shoulder_width / 2.0;
        let r_shoulder = Vec3::new(-half_sw, self.torso_length - self.shoulder_drop, 0.0);
        let l_shoulder = Vec3::new(half_sw, self.torso_length - self.shoulder_drop, 0.0);
        let r_hip = Vec3::new(-self.hip_width / 2.0, 0.0, 0.0);
        let l_hip = Vec3::new(self.hip_width / 2.0, 0.0, 0.0);

        let head = Mat3::rot_y(self.head_turn_deg.to_radians())
            * Mat3::rot_z(-self.head_tilt_deg.to_radians())
            * Mat3::rot_x(input.head_pitch_rad);
        let fwd = self.nose_forward_deg.to_radians();
        let nose = neck + head * Vec3::new(0.0, fwd.cos(), fwd.sin()) * self.neck_length;

        // Bow: the hair crosses the bowed string at the contact point.
        let s = input.string_index.clamp(0.0, 3.0);
        let contact = v.end_button + vrot * v.string_local(s, v.contact_from_bridge);
        let p = input.bow_position.clamp(0.0, 1.0);
        let tilt = Mat3::rot_y(-(self.bow.skew_at_tip_deg * p).to_radians())
            * Mat3::rot_z(self.string_angle(s));
        let bow_dir = vrot * (tilt * Vec3::X);
        let stick_up = vrot * (tilt * Vec3::Y);
        let hair_frog = contact - bow_dir * (self.bow.frog_margin + self.bow.hair_length * p);
        let frog = hair_frog + stick_up * STICK_AT_FROG;
        let tip = hair_frog + bow_dir * self.bow.length + stick_up * STICK_AT_TIP;
        let to_shoulder = (r_shoulder - frog).normalized_or(Vec3::Y);
        let hand_dir = (to_shoulder + stick_up * 0.6).normalized_or(Vec3::Y);
        let reach = self.hand_length - FLEX_PULL * input.right_flex.clamp(0.0, 1.0);
        let r_target = frog + hand_dir * reach;
        let right = two_link(
            r_shoulder,
            r_target,
            self.upper_arm,
            self.forearm,
            self.right_elbow_pole,
        );

        // Left hand: wrist under the neck, at the fingered place.
        let nut = v.bridge_from_end + v.string_length;
        let along =
            (nut - self.stop_distance(input.hand_semitones) + 0.01).max(v.body_length - 0.07);
        let l_target = on_violin(0.01, -0.05, along);
        let left = two_link(
            l_shoulder,
            l_target,
            self.upper_arm,
            self.forearm,
            self.left_elbow_pole,
        );

        let torso = Transform {
            rotation: Mat3::rot_z(input.hip_roll_rad) * Mat3::rot_x(input.torso_pitch_rad),
            translation: self.hip_centre() + Vec3::X * input.hip_shift_m,
        };
        let w = |p: Vec3| torso.apply(p);
        let mut joints = [Vec3::ZERO; JOINT_COUNT];
        for (joint, p) in [
            (Joint::Nose, nose),
            (Joint::Neck, neck),
            (Joint::RShoulder, r_shoulder),
            (Joint::RElbow, right.elbow),
            (Joint::RWrist, right.wrist),
            (Joint::LShoulder, l_shoulder),
            (Joint::LElbow, left.elbow),
            (Joint::LWrist, left.wrist),
            (Joint::RHip, r_hip),
            (Joint::LHip, l_hip),
        ] {
            joints[joint.index()] = w(p);
        }
        let mut instrument = [Vec3::ZERO; 4];
        for (i, point) in InstrumentPoint::ALL.into_iter().enumerate() {
            instrument[i] = w(match point {
                InstrumentPoint::BowFrog => frog,
                InstrumentPoint::BowTip => tip,
                InstrumentPoint::ViolinScroll => on_violin(0.0, 0.0, v.length),
                InstrumentPoint::ViolinBody => on_violin(0.0, 0.0, v.bridge_from_end),
            });
        }
        Pose {
            joints,
            instrument,
            reached: right.reached && left.reached,
            parts: PoseParts {
                torso,
                head,
                violin: vrot,
                hair_frog,
                bow_dir,
                stick_up,
                r_wrist: right.wrist,
                l_wrist: left.wrist,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(pose: &Pose, j: Joint) -> Vec3 {
        pose.joints[j.index()]
    }

    #[test]
    fn every_bow_position_and_string_is_reachable() {
        let rig = Rig::default();
        for s in 0..=12 {
            for p in 0..=20 {
                let input = PoseInput {
                    bow_position: p as f64 / 20.0,
                    string_index: s as f64 / 4.0,
                    hand_semitones: (s * 2) as f64,
                    ..PoseInput::default()
                };
                assert!(rig.pose(&input).reached, "string {s} bow {p}");
            }
        }
    }

    #[test]
    fn anatomy_is_plausible() {
        let rig = Rig::default();
        let pose = rig.pose(&PoseInput {
            bow_position: 0.5,
            string_index: 1.5,
            hand_semitones: 2.0,
            ..Default::default()
        });
        let nose = at(&pose, Joint::Nose);
        assert!(nose.y > at(&pose, Joint::Neck).y + 0.1, "head on top");
        assert!(
            at(&pose, Joint::LShoulder).x > at(&pose, Joint::RShoulder).x,
            "left is +x"
        );
        let scroll = pose.instrument[InstrumentPoint::ViolinScroll as usize];
        let body = pose.instrument[InstrumentPoint::ViolinBody as usize];
        assert!(
            scroll.x > body.x && scroll.z > body.z,
            "scroll forward-left"
        );
        let lw = at(&pose, Joint::LWrist);
        assert!(
            (lw - scroll).length() < 0.2,
            "left hand near the scroll in first position"
        );
        // G string: the right hand is higher than on the E string.
        let hand_y = |s: f64| {
            rig.pose(&PoseInput {
                string_index: s,
                bow_position: 0.5,
                ..Default::default()
            })
            .joints[Joint::RWrist.index()]
            .y
        };
        assert!(hand_y(0.0) > hand_y(3.0) + 0.05);
    }

    #[test]
    fn leaning_keeps_hips_and_bone_lengths() {
        let rig = Rig::default();
        let upright = rig.pose(&PoseInput::default());
        let lean = rig.pose(&PoseInput {
            torso_pitch_rad: 0.1,
            head_pitch_rad: -0.1,
            ..Default::default()
        });
        assert_eq!(at(&upright, Joint::RHip), at(&lean, Joint::RHip));
        assert!(
            at(&lean, Joint::Neck).z > at(&upright, Joint::Neck).z,
            "forward lean"
        );
        for (a, b) in skeleton::BONES {
            let l0 = (at(&upright, a) - at(&upright, b)).length();
            let l1 = (at(&lean, a) - at(&lean, b)).length();
            assert!((l0 - l1).abs() < 1e-9, "{a:?}-{b:?}");
        }
    }
}
