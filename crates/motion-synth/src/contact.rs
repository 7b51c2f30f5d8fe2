//! Contact metrics of a whole performer (issue #25): does the bow hair touch the string
//! being played, does the playing fingertip stop its string, how still are the hands.

use fingering::Fingering;
use performance::Note;
use skeleton::{InstrumentPart, Motion, PerformerPart};

use crate::geometry::Vec3;
use crate::violin::{point_segment_distance, segment_distance};

/// Tolerance of the contact metrics, metres.
pub const CONTACT_TOLERANCE_M: f64 = 0.005;

/// The part of a string the bow may play on, metres from the bridge (to the fingerboard's end).
const BOWING_ZONE_M: (f64, f64) = (0.0, 0.07);

/// The string (0 = G … 3 = E) sounding at each of `frames` frames at `fps`, `None` in
/// silence: the string of the latest note sounding there.
pub fn played_strings(
    notes: &[Note],
    fingerings: &[Fingering],
    fps: f64,
    frames: usize,
) -> Vec<Option<u8>> {
    let mut out = vec![None; frames];
    let frame_at = |t: f64| ((t * fps).ceil().max(0.0) as usize).min(frames);
    for (n, f) in notes.iter().zip(fingerings) {
        let s = f.string.number().saturating_sub(1).min(3);
        for slot in &mut out[frame_at(n.onset_s)..frame_at(n.offset_s).max(frame_at(n.onset_s))] {
            *slot = Some(s);
        }
    }
    out
}

fn point(track: &ndarray::Array3<f32>, f: usize, k: usize) -> Vec3 {
    Vec3::new(
        f64::from(track[[f, k, 0]]),
        f64::from(track[[f, k, 1]]),
        f64::from(track[[f, k, 2]]),
    )
}

/// Share of the frames with a played string (`played[f]`) in which the bow hair segment
/// passes within `tolerance_m` of that string's line between the bridge and the end of the
/// fingerboard (3-D). `None` without a 3-D performer track or without played frames.
pub fn bow_string_contact(motion: &Motion, played: &[Option<u8>], tolerance_m: f64) -> Option<f64> {
    let inst = motion.performer()?.track_3d(PerformerPart::Instrument)?;
    let (mut hit, mut total) = (0usize, 0usize);
    for (f, s) in played.iter().enumerate().take(motion.len()) {
        let Some(s) = *s else { continue };
        let bridge = point(inst, f, InstrumentPart::StringAtBridge(s).index());
        let nut = point(inst, f, InstrumentPart::StringAtNut(s).index());
        let along = (nut - bridge).normalized_or(Vec3::Z);
        let (a, b) = (
            bridge + along * BOWING_ZONE_M.0,
            bridge + along * BOWING_ZONE_M.1,
        );
        let hair = (
            point(inst, f, InstrumentPart::BowHairFrog.index()),
            point(inst, f, InstrumentPart::BowHairTip.index()),
        );
        total += 1;
        if segment_distance(hair.0, hair.1, a, b) <= tolerance_m {
            hit += 1;
        }
    }
    (total > 0).then(|| hit as f64 / total as f64)
}

/// Share of frames with a stopped note (`pressed[f]` = finger 1…4 and string) in which
/// that finger's tip lies within `tolerance_m` of its string's line (3-D). `None` without a
/// 3-D performer track or without stopped notes.
pub fn fingertip_string_contact(
    motion: &Motion,
    pressed: &[Option<(u8, u8)>],
    tolerance_m: f64,
) -> Option<f64> {
    let p = motion.performer()?;
    let inst = p.track_3d(PerformerPart::Instrument)?;
    let hand = p.track_3d(PerformerPart::LeftHand)?;
    let (mut hit, mut total) = (0usize, 0usize);
    for (f, press) in pressed.iter().enumerate().take(motion.len()) {
        let Some((finger, s)) = *press else { continue };
        let tip = point(
            hand,
            f,
            skeleton::Finger::ALL[usize::from(finger.clamp(1, 4))].tip(),
        );
        let bridge = point(inst, f, InstrumentPart::StringAtBridge(s).index());
        let nut = point(inst, f, InstrumentPart::StringAtNut(s).index());
        total += 1;
        if point_segment_distance(tip, bridge, nut).0 <= tolerance_m {
            hit += 1;
        }
    }
    (total > 0).then(|| hit as f64 / total as f64)
}

/// Mean 2-D acceleration of the hand points, pixels / frame²; `None` without hands.
pub fn hand_jitter_px(motion: &Motion) -> Option<f32> {
    motion.performer().map(|p| p.hand_jitter_px())
}
