//! Writing a motion's 3-D track as BVH.

use std::io::Write;
use std::path::Path;

use ndarray::Array3;

use super::euler::euler_zxy;
use crate::error::{Result, SkeletonError};
use crate::geometry::{Mat3, Vec3};
use crate::joint::Joint;
use crate::motion::Motion;

/// The BVH joints in file order.
pub const BVH_JOINTS: [&str; 12] = [
    "Hips",
    "RightHip",
    "LeftHip",
    "Spine",
    "Neck",
    "Head",
    "RightShoulder",
    "RightElbow",
    "RightWrist",
    "LeftShoulder",
    "LeftElbow",
    "LeftWrist",
];

/// The BVH joint whose position is `joint`'s (Head sits at the nose).
pub fn joint_for(joint: Joint) -> &'static str {
    match joint {
        Joint::Nose => "Head",
        Joint::Neck => "Neck",
        Joint::RShoulder => "RightShoulder",
        Joint::RElbow => "RightElbow",
        Joint::RWrist => "RightWrist",
        Joint::LShoulder => "LeftShoulder",
        Joint::LElbow => "LeftElbow",
        Joint::LWrist => "LeftWrist",
        Joint::RHip => "RightHip",
        Joint::LHip => "LeftHip",
    }
}

const CM: f64 = 100.0;

fn point(track: &Array3<f32>, f: usize, j: Joint) -> Vec3 {
    let i = j.index();
    Vec3::new(
        f64::from(track[[f, i, 0]]),
        f64::from(track[[f, i, 1]]),
        f64::from(track[[f, i, 2]]),
    )
}

/// Torso orientation: x along the hips (right → left), y towards the neck, z = x × y.
fn torso_frame(track: &Array3<f32>, f: usize) -> (Vec3, Mat3) {
    let (rh, lh) = (point(track, f, Joint::RHip), point(track, f, Joint::LHip));
    let centre = (rh + lh) * 0.5;
    let x = (lh - rh).normalized_or(Vec3::X);
    let up = point(track, f, Joint::Neck) - centre;
    let y = (up - x * up.dot(x)).normalized_or(Vec3::Y);
    (centre, Mat3::from_columns(x, y, x.cross(y)))
}

/// The rotation taking unit `a` onto unit `b` by the shortest arc.
fn shortest_arc(a: Vec3, b: Vec3) -> Mat3 {
    let axis = a.cross(b);
    let cos = a.dot(b).clamp(-1.0, 1.0);
    if axis.length() < 1e-12 {
        return if cos > 0.0 {
            Mat3::IDENTITY
        } else {
            Mat3::rot_x(std::f64::consts::PI)
        };
    }
    Mat3::axis_angle(axis.normalized_or(Vec3::X), cos.acos())
}

/// Segment frames of one arm in torso coordinates: rest direction `rest_sign · x`, bending
/// plane normal as local z. Returns (shoulder local, elbow local) rotations.
fn arm_rotations(upper: Vec3, fore: Vec3, rest_sign: f64, hinge: &mut Vec3) -> (Mat3, Mat3) {
    let e1 = upper.normalized_or(Vec3::X * rest_sign);
    let e2 = fore.normalized_or(e1);
    let n = e1.cross(e2);
    // A straight arm has no bending plane: keep the previous one (made perpendicular).
    let h = if n.length() > 1e-6 {
        n.normalized_or(*hinge)
    } else {
        *hinge
    };
    let h1 = (h - e1 * h.dot(e1)).normalized_or(Vec3::Z);
    *hinge = h1;
    let frame = |e: Vec3| {
        let c0 = e * rest_sign;
        let c2 = (h1 - e * h1.dot(e)).normalized_or(h1);
        Mat3::from_columns(c0, c2.cross(c0), c2)
    };
    let (fu, ff) = (frame(e1), frame(e2));
    (fu, fu.transpose() * ff)
}

fn mean<F: Fn(usize) -> f64>(frames: usize, f: F) -> f64 {
    (0..frames).map(f).sum::<f64>() / frames.max(1) as f64
}

/// Writes `motion`'s 3-D track as BVH (see the [module documentation](super)); a motion
/// with a 3-D performer track is written with the whole performer instead (body, fingers,
/// violin and bow: [`super::performer_joint_names`]). Fails when
/// the motion has no 3-D track, no frames or a non-finite coordinate.
pub fn write_bvh(motion: &Motion, mut out: impl Write) -> Result<()> {
    if let Some(p) = motion
        .performer()
        .filter(|p| p.track_3d(crate::PerformerPart::Body).is_some())
    {
        return super::performer::write_performer_bvh(motion, p, out);
    }
    let track = motion.frames_3d().ok_or(SkeletonError::MissingTrack {
        track: "3-D track",
        hint: "BVH needs 3-D joints; synthesize the motion with motion-synth",
    })?;
    let n = motion.len();
    if n == 0 {
        return Err(SkeletonError::MissingTrack {
            track: "frames",
            hint: "the motion is empty",
        });
    }
    if track.iter().any(|v| !v.is_finite()) {
        return Err(SkeletonError::MissingTrack {
            track: "finite 3-D coordinates",
            hint: "the 3-D track contains NaN or infinity",
        });
    }
    let local = |f: usize, j: Joint| {
        let (c, t) = torso_frame(track, f);
        t.transpose() * (point(track, f, j) - c)
    };
    let dist = |f: usize, a: Joint, b: Joint| (point(track, f, a) - point(track, f, b)).length();
    let hip_half = mean(n, |f| dist(f, Joint::RHip, Joint::LHip)) / 2.0 * CM;
    let torso = mean(n, |f| local(f, Joint::Neck).y) * CM;
    let head = mean(n, |f| dist(f, Joint::Neck, Joint::Nose)) * CM;
    let upper = |s: Joint, e: Joint| mean(n, |f| dist(f, s, e)) * CM;
    let shoulder = |j: Joint| {
        let m = |c: fn(Vec3) -> f64| mean(n, |f| c(local(f, j))) * CM;
        Vec3::new(m(|v| v.x), m(|v| v.y) - torso / 2.0, m(|v| v.z))
    };
    let (rs, ls) = (shoulder(Joint::RShoulder), shoulder(Joint::LShoulder));
    let (ru, rf) = (
        upper(Joint::RShoulder, Joint::RElbow),
        upper(Joint::RElbow, Joint::RWrist),
    );
    let (lu, lf) = (
        upper(Joint::LShoulder, Joint::LElbow),
        upper(Joint::LElbow, Joint::LWrist),
    );

    let rot3 = "CHANNELS 3 Zrotation Xrotation Yrotation";
    let fmt = |v: Vec3| format!("OFFSET {:.4} {:.4} {:.4}", v.x, v.y, v.z);
    let mut h = String::with_capacity(4096);
    let mut line = |depth: usize, text: &str| {
        h.push_str(&"\t".repeat(depth));
        h.push_str(text);
        h.push('\n');
    };
    line(0, "HIERARCHY");
    line(0, "ROOT Hips");
    line(0, "{");
    line(1, &fmt(Vec3::ZERO));
    line(
        1,
        "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
    );
    for (name, sign) in [("RightHip", -1.0), ("LeftHip", 1.0)] {
        for (d, t) in [
            (1, format!("JOINT {name}")),
            (1, "{".into()),
            (2, fmt(Vec3::X * (sign * hip_half))),
            (2, rot3.into()),
            (2, "End Site".into()),
            (2, "{".into()),
            (3, fmt(Vec3::Y * -45.0)),
            (2, "}".into()),
            (1, "}".into()),
        ] {
            line(d, &t);
        }
    }
    line(1, "JOINT Spine");
    line(1, "{");
    line(2, &fmt(Vec3::Y * (torso / 2.0)));
    line(2, rot3);
    for (d, t) in [
        (2, "JOINT Neck".to_string()),
        (2, "{".into()),
        (3, fmt(Vec3::Y * (torso / 2.0))),
        (3, rot3.into()),
        (3, "JOINT Head".into()),
        (3, "{".into()),
        (4, fmt(Vec3::Y * head)),
        (4, rot3.into()),
        (4, "End Site".into()),
        (4, "{".into()),
        (5, fmt(Vec3::Y * 10.0)),
        (4, "}".into()),
        (3, "}".into()),
        (2, "}".into()),
    ] {
        line(d, &t);
    }
    for (side, off, up, fo, sign) in [("Right", rs, ru, rf, -1.0), ("Left", ls, lu, lf, 1.0)] {
        for (d, t) in [
            (2, format!("JOINT {side}Shoulder")),
            (2, "{".into()),
            (3, fmt(off)),
            (3, rot3.into()),
            (3, format!("JOINT {side}Elbow")),
            (3, "{".into()),
            (4, fmt(Vec3::X * (sign * up))),
            (4, rot3.into()),
            (4, format!("JOINT {side}Wrist")),
            (4, "{".into()),
            (5, fmt(Vec3::X * (sign * fo))),
            (5, rot3.into()),
            (5, "End Site".into()),
            (5, "{".into()),
            (6, fmt(Vec3::X * (sign * 8.0))),
            (5, "}".into()),
            (4, "}".into()),
            (3, "}".into()),
            (2, "}".into()),
        ] {
            line(d, &t);
        }
    }
    line(1, "}");
    line(0, "}");
    line(0, "MOTION");
    line(0, &format!("Frames: {n}"));
    line(0, &format!("Frame Time: {:.7}", 1.0 / motion.fps()));
    out.write_all(h.as_bytes())?;

    let zero = [0.0; 3];
    let mut prev: Option<Vec<f64>> = None;
    let mut hinges = [Vec3::Z, Vec3::Z];
    let mut row = Vec::with_capacity(6 + 11 * 3);
    let mut text = String::with_capacity(512);
    for f in 0..n {
        let (centre, t) = torso_frame(track, f);
        let to_local = |j: Joint| t.transpose() * (point(track, f, j) - centre);
        let nose_dir = to_local(Joint::Nose) - to_local(Joint::Neck);
        let neck = shortest_arc(Vec3::Y, nose_dir.normalized_or(Vec3::Y));
        let arm = |s: Joint, e: Joint, w: Joint, sign: f64, hinge: &mut Vec3| {
            let (sh, el, wr) = (to_local(s), to_local(e), to_local(w));
            arm_rotations(el - sh, wr - el, sign, hinge)
        };
        let (r_sh, r_el) = arm(
            Joint::RShoulder,
            Joint::RElbow,
            Joint::RWrist,
            -1.0,
            &mut hinges[0],
        );
        let (l_sh, l_el) = arm(
            Joint::LShoulder,
            Joint::LElbow,
            Joint::LWrist,
            1.0,
            &mut hinges[1],
        );
        row.clear();
        row.extend((centre * CM).to_array());
        row.extend(euler_zxy(&t));
        row.extend(zero); // RightHip
        row.extend(zero); // LeftHip
        row.extend(zero); // Spine
        row.extend(euler_zxy(&neck));
        row.extend(zero); // Head
        row.extend(euler_zxy(&r_sh));
        row.extend(euler_zxy(&r_el));
        row.extend(zero); // RightWrist
        row.extend(euler_zxy(&l_sh));
        row.extend(euler_zxy(&l_el));
        row.extend(zero); // LeftWrist
                          // Keep each angle within 180° of the previous frame's (same rotation, no wrap jumps).
        if let Some(p) = &prev {
            for (v, q) in row.iter_mut().zip(p).skip(3) {
                *v -= 360.0 * ((*v - q) / 360.0).round();
            }
        }
        super::fixed::write_frame_line(&mut out, &mut text, &row)?;
        match &mut prev {
            Some(p) => p.clone_from(&row),
            None => prev = Some(row.clone()),
        }
    }
    out.flush()?;
    Ok(())
}

/// [`write_bvh`] to a file, atomically: a temporary file beside `path` is renamed into
/// place at the end, so a failure leaves no half-written file.
pub fn write_bvh_file(motion: &Motion, path: impl AsRef<Path>) -> Result<()> {
    let path = path.as_ref();
    atomic_file::write_atomically(path, |w| write_bvh(motion, w)).map_err(|e| match e {
        atomic_file::AtomicWriteError::Io(source) => SkeletonError::Io {
            path: path.to_path_buf(),
            source,
        },
        atomic_file::AtomicWriteError::Write(e) => e,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shortest_arc_maps_a_onto_b() {
        let a = Vec3::Y;
        for b in [Vec3::new(0.2, 0.9, 0.4), -Vec3::Y, Vec3::Y] {
            let b = b.normalized_or(Vec3::Y);
            assert!((shortest_arc(a, b) * a - b).length() < 1e-12);
        }
    }
}
