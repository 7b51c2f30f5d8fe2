//! What pose estimators do to a clean track: jitter, low and uneven confidences, the far
//! side occluded, dropouts, left/right swaps, frames without the performer, bystanders
//! (one larger than the performer), a person walking into the frame and staying, one-frame
//! false detections. Seeded through the caller's [`Rng`].

use skeleton::{Joint, PoseLayout, JOINT_COUNT};

use super::{bystander, keypoints, Rng};

/// Image size of every clip.
pub const WIDTH: f64 = 1280.0;
pub const HEIGHT: f64 = 720.0;

/// What the troubles need to know of the camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    pub fps: f64,
    /// Performer's height (nose to hips), pixels.
    pub height_px: f64,
    pub yaw_deg: f64,
    pub layout: PoseLayout,
}

/// Rates and sizes of the troubles.
#[derive(Debug, Clone, PartialEq)]
pub struct Troubles {
    /// Gaussian jitter, fraction of the performer's height (at least 0.7 px); wrists 1.5×.
    pub jitter_frac: f64,
    /// Dropouts (1–3 joints missing for 0.03–0.33 s) per second.
    pub dropouts_per_s: f64,
    /// Left/right swaps of every pair for 1–6 frames, per second (doubled in side views).
    pub swaps_per_s: f64,
    /// Frames without the performer (1–3 frames) per second.
    pub absences_per_s: f64,
    /// Stretches of 1–3 s with all confidences at 0.1–0.35, per 10 s.
    pub low_confidence_per_10s: f64,
    /// Standing bystanders (one of them 1.0–1.5× the performer's size, from 30 % of the
    /// clip on; the others 0.6–1.2×, for 2–8 s stretches).
    pub bystanders: usize,
    /// A person who walks in from the image's edge over 2 s and stays to the end.
    pub entering: bool,
    /// One-frame false detections (1.3× the performer, beside them) per second.
    pub false_per_s: f64,
    /// Joints more than 8 cm behind the neck get confidences 0.1–0.4 (15 %: missing).
    pub occlusion: bool,
}

impl Troubles {
    pub fn standard() -> Troubles {
        Troubles {
            jitter_frac: 0.01,
            dropouts_per_s: 0.5,
            swaps_per_s: 0.1,
            absences_per_s: 0.1,
            low_confidence_per_10s: 1.0,
            bystanders: 2,
            entering: true,
            false_per_s: 0.2,
            occlusion: true,
        }
    }

    /// Turns one trouble off by name (see the fields; `occlusion` is the far side's).
    pub fn disable(&mut self, name: &str) {
        match name {
            "jitter" => self.jitter_frac = 0.0,
            "dropouts" => self.dropouts_per_s = 0.0,
            "swaps" => self.swaps_per_s = 0.0,
            "absences" => self.absences_per_s = 0.0,
            "low_confidence" => self.low_confidence_per_10s = 0.0,
            "occlusion" => self.occlusion = false,
            "bystanders" => self.bystanders = 0,
            "entering" => self.entering = false,
            "false" => self.false_per_s = 0.0,
            other => panic!("unknown trouble {other}"),
        }
    }

    pub fn none() -> Troubles {
        Troubles {
            jitter_frac: 0.0,
            dropouts_per_s: 0.0,
            swaps_per_s: 0.0,
            absences_per_s: 0.0,
            low_confidence_per_10s: 0.0,
            bystanders: 0,
            entering: false,
            false_per_s: 0.0,
            occlusion: false,
        }
    }
}

fn count(rng: &mut Rng, expected: f64) -> usize {
    (expected + f64::from(rng.uniform()) - 0.5).round().max(0.0) as usize
}

fn in_image(p: [f32; 2]) -> bool {
    p[0] >= 0.0 && p[1] >= 0.0 && f64::from(p[0]) < WIDTH && f64::from(p[1]) < HEIGHT
}

/// A standing person of `height_px` (nose to hips) whose hips' midpoint is at `(x, y)`.
fn standing(t: usize, x: f32, y: f32, height_px: f32) -> [[f32; 2]; JOINT_COUNT] {
    let scale = height_px / 280.0;
    bystander(t, x, y - 120.0 * scale, scale)
}

/// The people of every frame (keypoint arrays of the clip's layout).
pub fn add_troubles(
    truth: &[[[f32; 2]; JOINT_COUNT]],
    behind_m: &[[f32; JOINT_COUNT]],
    tr: &Troubles,
    cam: &View,
    rng: &mut Rng,
) -> Vec<Vec<Vec<f32>>> {
    let fps = cam.fps;
    let n = truth.len();
    let dur = n as f64 / fps;
    let h = cam.height_px as f32;
    let sigma = (tr.jitter_frac * cam.height_px).max(0.7) as f32;
    let sigma = if tr.jitter_frac > 0.0 { sigma } else { 0.0 };

    let mut conf = vec![[0.0f32; JOINT_COUNT]; n];
    for (t, c) in conf.iter_mut().enumerate() {
        for j in 0..JOINT_COUNT {
            c[j] = 0.55 + 0.4 * rng.uniform();
            // The far side, more than 8 cm behind the neck, is partly occluded.
            if tr.occlusion && behind_m.get(t).is_some_and(|b| b[j] > 0.08) {
                c[j] = if rng.uniform() < 0.15 {
                    0.0
                } else {
                    0.1 + 0.3 * rng.uniform()
                };
            }
        }
    }
    for _ in 0..count(rng, tr.low_confidence_per_10s * dur / 10.0) {
        let start = rng.int(0, n - 1);
        let len = (fps * (1.0 + 2.0 * f64::from(rng.uniform()))) as usize;
        for c in conf.iter_mut().skip(start).take(len) {
            for v in c.iter_mut().filter(|v| **v > 0.0) {
                *v = 0.1 + 0.25 * rng.uniform();
            }
        }
    }
    for _ in 0..count(rng, tr.dropouts_per_s * dur) {
        let start = rng.int(0, n - 1);
        let len = ((0.03 + 0.3 * f64::from(rng.uniform())) * fps).ceil() as usize;
        for _ in 0..rng.int(1, 3) {
            let j = rng.int(0, JOINT_COUNT - 1);
            for c in conf.iter_mut().skip(start).take(len) {
                c[j] = 0.0;
            }
        }
    }
    let mut swapped = vec![false; n];
    let side = if cam.yaw_deg.abs() > 45.0 { 2.0 } else { 1.0 };
    for _ in 0..count(rng, side * tr.swaps_per_s * dur) {
        let (start, len) = (rng.int(0, n - 1), rng.int(1, 6));
        for s in swapped.iter_mut().skip(start).take(len) {
            *s = true;
        }
    }
    let mut absent = vec![false; n];
    for _ in 0..count(rng, tr.absences_per_s * dur) {
        let (start, len) = (rng.int(0, n - 1), rng.int(1, 3));
        for a in absent.iter_mut().skip(start).take(len) {
            *a = true;
        }
    }
    // Where the performer stands: hips' midpoint, mean over the clip.
    let (rh, lh) = (Joint::RHip.index(), Joint::LHip.index());
    let px = truth
        .iter()
        .map(|p| (p[rh][0] + p[lh][0]) / 2.0)
        .sum::<f32>()
        / n as f32;
    let py = truth
        .iter()
        .map(|p| (p[rh][1] + p[lh][1]) / 2.0)
        .sum::<f32>()
        / n as f32;
    let elsewhere = |rng: &mut Rng| {
        let away = h * (1.0 + 0.8 * rng.uniform());
        let x = if px > WIDTH as f32 / 2.0 {
            px - away
        } else {
            px + away
        };
        (x, py + 0.2 * h * (rng.uniform() - 0.5))
    };
    let mut others: Vec<Vec<Option<[[f32; 2]; JOINT_COUNT]>>> = Vec::new();
    for b in 0..tr.bystanders {
        let (x, y) = elsewhere(rng);
        let mut track = vec![None; n];
        let (start, len, size) = if b == 0 {
            (n * 3 / 10, n, h * (1.0 + 0.5 * rng.uniform()))
        } else {
            let len = (fps * (2.0 + 6.0 * f64::from(rng.uniform()))) as usize;
            (rng.int(0, n - 1), len, h * (0.6 + 0.6 * rng.uniform()))
        };
        for (t, slot) in track.iter_mut().enumerate().skip(start).take(len) {
            *slot = Some(standing(t, x, y, size));
        }
        others.push(track);
    }
    if tr.entering {
        let (x, y) = elsewhere(rng);
        let from = if x > px { WIDTH as f32 + h } else { -h };
        let start = rng.int(n / 5, n / 2);
        let walk = (2.0 * fps) as usize;
        let size = h * (0.8 + 0.4 * rng.uniform());
        let mut track = vec![None; n];
        for (t, slot) in track.iter_mut().enumerate().skip(start) {
            let u = ((t - start) as f32 / walk as f32).min(1.0);
            *slot = Some(standing(t, from + u * (x - from), y, size));
        }
        others.push(track);
    }
    let mut false_at = vec![false; n];
    for _ in 0..count(rng, tr.false_per_s * dur) {
        false_at[rng.int(0, n - 1)] = true;
    }

    let layout = cam.layout;
    let mut people = Vec::with_capacity(n);
    let jitter = |rng: &mut Rng, j: usize| {
        let wrist = j == Joint::RWrist.index() || j == Joint::LWrist.index();
        sigma * if wrist { 1.5 } else { 1.0 } * rng.normal()
    };
    for t in 0..n {
        let mut frame: Vec<Vec<f32>> = Vec::new();
        if !absent[t] {
            let mut pose = [[0.0f32; 2]; JOINT_COUNT];
            let mut c = conf[t];
            for j in 0..JOINT_COUNT {
                pose[j] = [
                    truth[t][j][0] + jitter(rng, j),
                    truth[t][j][1] + jitter(rng, j),
                ];
                if !in_image(pose[j]) {
                    c[j] = 0.0;
                }
            }
            if swapped[t] {
                for (r, l) in [(2, 5), (3, 6), (4, 7), (8, 9)] {
                    pose.swap(r, l);
                    c.swap(r, l);
                }
            }
            frame.push(keypoints(layout, &pose, &c));
        }
        for track in &others {
            if let Some(b) = track[t] {
                let mut c: [f32; JOINT_COUNT] = std::array::from_fn(|_| 0.4 + 0.5 * rng.uniform());
                for j in 0..JOINT_COUNT {
                    if !in_image(b[j]) {
                        c[j] = 0.0;
                    }
                }
                if c.iter().filter(|v| **v > 0.0).count() >= 3 {
                    frame.push(keypoints(layout, &b, &c));
                }
            }
        }
        if false_at[t] && !absent[t] {
            let dx = h * (0.6 + 0.4 * rng.uniform()) * if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
            let pose = truth[t].map(|[x, y]| [px + (x - px) * 1.3 + dx, py + (y - py) * 1.3]);
            frame.push(keypoints(layout, &pose, &[0.97; JOINT_COUNT]));
        }
        if frame.len() > 1 {
            let k = rng.int(0, frame.len() - 1);
            frame.swap(0, k);
        }
        people.push(frame);
    }
    people
}
