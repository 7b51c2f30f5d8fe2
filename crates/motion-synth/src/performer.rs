//! The whole performer per frame: BODY_25 body (legs on the floor, eyes and ears with the
//! head), both 21-point hands and the violin and bow parts, built from the rig's pose.
//!
//! * **Left fingers** follow the fingering: the playing finger's tip lies on its string at
//!   `L · 2^(−semitones/12)` from the bridge (vibrato rocks it ±2.5 mm along the string at
//!   5.5 Hz on notes of 0.35 s or more); the other fingers hover 1 cm above their places,
//!   the next note's finger descends onto its place in the 0.15 s before its onset. Open
//!   strings put no finger down. Hovering fingers follow their targets with a 50 ms lag.
//! * **Right fingers** hold the stick (thumb under it, little finger on top); at bow
//!   changes the wrist comes closer to the frog, so the fingers flex.
//! * **Legs**: the feet stay on the floor; the knees follow the hips' weight shift (IK).

use fingering::Fingering;
use performance::Note;
use skeleton::{BodyPoint, InstrumentPart, Joint, HAND_POINT_COUNT, INSTRUMENT_PART_COUNT};

use crate::geometry::{smoothstep, Vec3};
use crate::hands::{
    hand_points, right_hand_frame, LEFT_BASES_LOCAL, RIGHT_BASES_LOCAL, RIGHT_GRIP,
};
use crate::ik::two_link;
use crate::rig::{Pose, Rig};

/// A finger stopping a string.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Press {
    /// Finger 1 (index) … 4 (little finger).
    pub finger: u8,
    /// String, 0 = G … 3 = E.
    pub string: u8,
    /// Semitones above the open string.
    pub semitones: f64,
    /// Vibrato displacement along the string at this frame, metres (+ towards the nut).
    pub vibrato_m: f64,
}

/// What the left fingers do at one frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FingerFrame {
    /// The finger down on its string (a stopped note sounds), if any.
    pub down: Option<Press>,
    /// The next note's finger preparing, with how far it has come down (0 … 1).
    pub next: Option<(Press, f64)>,
    /// The finger of a double stop's second note, down on its string, if stopped.
    pub also_down: Option<Press>,
}

/// The press of a stopped place (`None` for an open string).
fn press_of(f: &Fingering) -> Option<Press> {
    (f.finger != 0).then(|| Press {
        finger: f.finger.min(4),
        string: f.string.number().saturating_sub(1).min(3),
        semitones: f64::from(f.semitones_above_open()),
        vibrato_m: 0.0,
    })
}

const VIBRATO_HZ: f64 = 5.5;
const VIBRATO_M: f64 = 0.0025;
const VIBRATO_MIN_NOTE_S: f64 = 0.35;
const PREPARE_S: f64 = 0.15;
const HOVER_M: f64 = 0.010;
const FOLLOW_S: f64 = 0.05;

/// The left fingers' plan for `frames` frames at `fps` from the notes and their fingerings,
/// and the second notes of double stops with their places (`None`: not shown).
pub fn finger_plan(
    notes: &[Note],
    fingerings: &[Fingering],
    double_stops: &[(Note, Option<Fingering>)],
    fps: f64,
    frames: usize,
) -> Vec<FingerFrame> {
    let mut plan = vec![FingerFrame::default(); frames];
    let frame_at = |t: f64| ((t * fps).ceil().max(0.0) as usize).min(frames);
    for (note, f) in double_stops {
        let Some(press) = f.as_ref().and_then(press_of) else {
            continue;
        };
        let (from, to) = (frame_at(note.onset_s), frame_at(note.offset_s));
        for slot in plan.iter_mut().take(to).skip(from) {
            slot.also_down = Some(press);
        }
    }
    for (note, f) in notes.iter().zip(fingerings) {
        let Some(press) = press_of(f) else {
            continue;
        };
        let long = note.offset_s - note.onset_s >= VIBRATO_MIN_NOTE_S;
        for (i, slot) in plan
            .iter_mut()
            .enumerate()
            .take(frame_at(note.offset_s))
            .skip(frame_at(note.onset_s))
        {
            let t = i as f64 / fps - note.onset_s;
            let vibrato_m = if long {
                let fade = smoothstep((t - 0.12) / 0.2)
                    * smoothstep((note.offset_s - note.onset_s - t) / 0.1);
                VIBRATO_M * fade * (std::f64::consts::TAU * VIBRATO_HZ * t).sin()
            } else {
                0.0
            };
            slot.down = Some(Press { vibrato_m, ..press });
        }
        let start = note.onset_s - PREPARE_S;
        for (i, slot) in plan
            .iter_mut()
            .enumerate()
            .take(frame_at(note.onset_s))
            .skip(frame_at(start))
        {
            if slot.down.is_some_and(|d| d.finger == press.finger) {
                continue;
            }
            let w = smoothstep((i as f64 / fps - start) / PREPARE_S);
            slot.next = Some((press, w));
        }
    }
    plan
}

/// One frame of the whole performer, world metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PerformerPose {
    /// BODY_25 points.
    pub body: [Vec3; 25],
    /// Left hand, 21 points.
    pub left_hand: [Vec3; HAND_POINT_COUNT],
    /// Right hand, 21 points.
    pub right_hand: [Vec3; HAND_POINT_COUNT],
    /// Violin and bow parts ([`InstrumentPart::ALL`]).
    pub instrument: [Vec3; INSTRUMENT_PART_COUNT],
}

/// Builds [`PerformerPose`]s frame after frame (it keeps the hovering fingers' state).
#[derive(Debug, Clone)]
pub struct PerformerBuilder {
    fingers_local: Option<[Vec3; 4]>,
    follow: f64,
}

/// Ankle, heel, big toe and small toe of the right foot (world metres); the left foot is
/// the mirror image, a little forward.
const RIGHT_FOOT: [Vec3; 4] = [
    Vec3::new(-0.13, 0.08, -0.03),
    Vec3::new(-0.12, 0.03, -0.09),
    Vec3::new(-0.16, 0.01, 0.13),
    Vec3::new(-0.21, 0.01, 0.10),
];
const LEFT_FORWARD_M: f64 = 0.06;
const THIGH_M: f64 = 0.45;
const SHIN_M: f64 = 0.43;

/// Eyes and ears in the head frame (relative to the neck), right then left.
const EYES_EARS: [(BodyPoint, Vec3); 4] = [
    (BodyPoint::REye, Vec3::new(-0.032, 0.215, 0.068)),
    (BodyPoint::LEye, Vec3::new(0.032, 0.215, 0.068)),
    (BodyPoint::REar, Vec3::new(-0.072, 0.185, -0.005)),
    (BodyPoint::LEar, Vec3::new(0.072, 0.185, -0.005)),
];

impl PerformerBuilder {
    /// A builder for frames `1 / fps` apart.
    pub fn new(fps: f64) -> Self {
        PerformerBuilder {
            fingers_local: None,
            follow: 1.0 - (-1.0 / (fps * FOLLOW_S)).exp(),
        }
    }

    /// The performer at one frame: `pose` from [`Rig::pose`], the fingers' plan, the bowed
    /// string (continuous index) and the hand's place (semitones).
    pub fn frame(
        &mut self,
        rig: &Rig,
        pose: &Pose,
        fingers: &FingerFrame,
        string_index: f64,
        hand_semitones: f64,
    ) -> PerformerPose {
        let parts = &pose.parts;
        let torso = parts.torso;
        let v = &rig.violin;
        let violin = |local: Vec3| torso.apply(v.end_button + parts.violin * local);

        let mut body = [Vec3::ZERO; 25];
        for j in Joint::ALL {
            body[BodyPoint::of_joint(j).index()] = pose.joints[j.index()];
        }
        body[BodyPoint::MidHip.index()] = torso.translation;
        let neck = Vec3::new(0.0, rig.torso_length, 0.0);
        for (point, local) in EYES_EARS {
            body[point.index()] = torso.apply(neck + parts.head * local);
        }
        for (left, [hip, knee, ankle, heel, big, small]) in [
            (
                false,
                [
                    BodyPoint::RHip,
                    BodyPoint::RKnee,
                    BodyPoint::RAnkle,
                    BodyPoint::RHeel,
                    BodyPoint::RBigToe,
                    BodyPoint::RSmallToe,
                ],
            ),
            (
                true,
                [
                    BodyPoint::LHip,
                    BodyPoint::LKnee,
                    BodyPoint::LAnkle,
                    BodyPoint::LHeel,
                    BodyPoint::LBigToe,
                    BodyPoint::LSmallToe,
                ],
            ),
        ] {
            let place = |p: Vec3| {
                if left {
                    Vec3::new(-p.x, p.y, p.z + LEFT_FORWARD_M)
                } else {
                    p
                }
            };
            let foot = RIGHT_FOOT.map(place);
            let side = if left { 1.0 } else { -1.0 };
            let leg = two_link(
                body[hip.index()],
                foot[0],
                THIGH_M,
                SHIN_M,
                Vec3::new(0.15 * side, 0.0, 1.0),
            );
            body[knee.index()] = leg.elbow;
            body[ankle.index()] = leg.wrist;
            let shift = leg.wrist - foot[0];
            for (point, p) in [(heel, foot[1]), (big, foot[2]), (small, foot[3])] {
                body[point.index()] = p + shift;
            }
        }

        let mut instrument = [Vec3::ZERO; INSTRUMENT_PART_COUNT];
        for part in InstrumentPart::ALL {
            if let Some(local) = v.part_local(part) {
                instrument[part.index()] = violin(local);
            }
        }
        let rot = torso.rotation;
        let bow_dir = rot * parts.bow_dir;
        let stick_up = rot * parts.stick_up;
        let hair_frog = torso.apply(parts.hair_frog);
        let frog = pose.instrument[skeleton::InstrumentPoint::BowFrog as usize];
        instrument[InstrumentPart::BowFrog.index()] = frog;
        instrument[InstrumentPart::BowTip.index()] =
            pose.instrument[skeleton::InstrumentPoint::BowTip as usize];
        instrument[InstrumentPart::BowHairFrog.index()] = hair_frog + bow_dir * 0.01;
        instrument[InstrumentPart::BowHairTip.index()] =
            hair_frog + bow_dir * (rig.bow.length - 0.005);

        // Right hand: a stable grip on the stick.
        let r_wrist = pose.joints[Joint::RWrist.index()];
        let frame = right_hand_frame(r_wrist, frog, bow_dir);
        let away = frame.column(0);
        let away = (away - bow_dir * away.dot(bow_dir)).normalized_or(away);
        let r_bases = RIGHT_BASES_LOCAL.map(|b| r_wrist + frame * b);
        let r_targets = RIGHT_GRIP.map(|[a, u, w]| frog + bow_dir * a + stick_up * u + away * w);
        let right_hand = hand_points(r_wrist, &r_bases, &r_targets, stick_up - away * 0.5);

        // Left hand: the fingering.
        let l_wrist = pose.joints[Joint::LWrist.index()];
        let hand_rot = rot * parts.violin;
        let l_bases = LEFT_BASES_LOCAL.map(|b| l_wrist + hand_rot * b);
        let place = |string: f64, semitones: f64, extra_m: f64| {
            v.string_local(string, v.stop_from_bridge(semitones) + extra_m)
        };
        let hover_string = fingers.down.map_or(string_index, |d| f64::from(d.string));
        let mut local = [Vec3::ZERO; 4];
        for (k, slot) in local.iter_mut().enumerate() {
            let natural = hand_semitones + [0.0, 2.0, 3.0, 5.0][k];
            *slot = place(hover_string, natural, 0.0) + Vec3::Y * HOVER_M;
            if let Some((next, w)) = fingers.next.filter(|(n, _)| usize::from(n.finger) == k + 1) {
                let target = place(f64::from(next.string), next.semitones, 0.0) + Vec3::Y * 0.001;
                *slot = *slot + (target - *slot) * w;
            }
        }
        let mut state = match self.fingers_local {
            Some(prev) => std::array::from_fn(|k| prev[k] + (local[k] - prev[k]) * self.follow),
            None => local,
        };
        for d in [fingers.also_down, fingers.down].into_iter().flatten() {
            let k = usize::from(d.finger.clamp(1, 4)) - 1;
            state[k] = place(f64::from(d.string), d.semitones, d.vibrato_m);
        }
        self.fingers_local = Some(state);
        let thumb_at = v.bridge_from_end + v.stop_from_bridge(hand_semitones) - 0.01;
        let mut l_targets = [violin(Vec3::new(0.018, 0.004, thumb_at)); 5];
        for k in 0..4 {
            l_targets[k + 1] = violin(state[k]);
        }
        let l_pole = hand_rot * Vec3::new(-0.6, 1.0, 0.0);
        let left_hand = hand_points(l_wrist, &l_bases, &l_targets, l_pole);

        PerformerPose {
            body,
            left_hand,
            right_hand,
            instrument,
        }
    }
}
