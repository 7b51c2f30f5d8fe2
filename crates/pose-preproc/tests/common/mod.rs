//! A seeded generator of synthetic OpenPose output: a violinist whose right wrist strokes up
//! and down with bow changes at known frames, plus the troubles of real output (jitter,
//! dropouts, frames without the performer, a bystander, one-frame false detections).
//! Shared by the integration tests and the examples. [`camera_clip`] makes clips from the
//! project's motion synthesis seen through random cameras.
#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)]

pub mod camera_clip;
pub mod troubles;

use std::path::Path;

use ndarray::Array3;
use skeleton::{Joint, PoseLayout, JOINT_COUNT};

/// splitmix64: small, seeded, good enough for test data.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed ^ 0x5DEE_CE66_D1CE_4E5B)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
    /// Uniform integer in lo..=hi.
    pub fn int(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }
    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f32 {
        let u1 = self.uniform().max(1e-7);
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f32::consts::PI * u2).cos()
    }
}

/// What to generate.
#[derive(Debug, Clone)]
pub struct SynthConfig {
    pub frames: usize,
    pub layout: PoseLayout,
    pub seed: u64,
    /// Gaussian jitter (px, standard deviation) on every keypoint coordinate.
    pub jitter_px: f32,
    /// Short dropouts (1–3 joints at confidence 0 for 1–10 frames) per 100 frames.
    pub dropouts_per_100_frames: f32,
    /// Windows of 1–3 frames without the performer, per 100 frames.
    pub absences_per_100_frames: f32,
    /// A second, standing person in some stretches of the clip.
    pub bystander: bool,
    /// One-frame false detections next to the performer, per 100 frames.
    pub false_detections_per_100_frames: f32,
    /// A long dropout of one joint: (joint, first frame, frames).
    pub long_dropout: Option<(Joint, usize, usize)>,
}

impl SynthConfig {
    /// The standard test clip: 3 px jitter, a dropout every 2 s, a one-frame absence every
    /// 10 s, a bystander, a false detection every 5 s.
    pub fn standard(frames: usize, layout: PoseLayout, seed: u64) -> Self {
        Self {
            frames,
            layout,
            seed,
            jitter_px: 3.0,
            dropouts_per_100_frames: 1.667,
            absences_per_100_frames: 0.333,
            bystander: true,
            false_detections_per_100_frames: 0.667,
            long_dropout: None,
        }
    }
}

/// A generated clip: ground truth and the OpenPose frames.
pub struct SynthClip {
    pub layout: PoseLayout,
    /// The performer's true joints (no jitter), (T, 10, 2) px.
    pub truth: Array3<f32>,
    /// Frames where the bow reverses (the extremum of the wrist's travel).
    pub bow_changes: Vec<usize>,
    /// Frames in which the performer is absent from the file.
    pub absent_frames: Vec<usize>,
    /// Frames holding a one-frame false detection.
    pub false_detection_frames: Vec<usize>,
    /// Frames in which the bystander is present.
    pub bystander_frames: usize,
    /// `people[t]`: keypoint arrays (layout count × 3) of the people of frame t.
    pub people: Vec<Vec<Vec<f32>>>,
}

/// Pixels of a full bow along the wrist's path: x −170, y +140 from frog to tip.
const BOW_DX: f32 = -170.0;
const BOW_DY: f32 = 140.0;
const FULL_BOW_FRAMES: f32 = 28.0;

/// The bow position per frame (0 = frog, 1 = tip) and the change frames.
///
/// Stroke lengths are uniform in 8–60 frames and the direction alternates. As in SPEC §5, a
/// stroke shorter than 15 frames travels `len/28` of the bow and a longer one the whole bow
/// (so short strokes are fast, long ones slower). Partial strokes make the position drift;
/// the drift is removed with a centred 91-frame moving average (the player re-places the
/// arm slowly), which leaves the reversals where they were. The change frames are the
/// extrema of the final track.
fn bow_track(frames: usize, rng: &mut Rng) -> (Vec<f32>, Vec<usize>) {
    let mut raw = vec![0.0f32; frames];
    let mut nominal = Vec::new();
    let (mut p, mut dir, mut t) = (0.0f32, 1.0f32, 0usize);
    while t < frames {
        let len = rng.int(8, 60);
        let travel = if len < 15 {
            len as f32 / FULL_BOW_FRAMES
        } else {
            1.0
        };
        let speed = travel / (len as f32 - 2.0);
        for k in 0..len {
            if t >= frames {
                break;
            }
            raw[t] = p;
            // Ease in and out over two frames at each end of the stroke.
            let ramp = ((k as f32 + 0.5) / 2.0)
                .min((len as f32 - k as f32 - 0.5) / 2.0)
                .min(1.0);
            p += dir * speed * ramp;
            t += 1;
        }
        if t < frames {
            nominal.push(t);
        }
        dir = -dir;
    }
    let half = 45usize;
    let mut prefix = vec![0.0f64; frames + 1];
    for (i, v) in raw.iter().enumerate() {
        prefix[i + 1] = prefix[i] + f64::from(*v);
    }
    let pos: Vec<f32> = (0..frames)
        .map(|i| {
            let (a, b) = (i.saturating_sub(half), (i + half + 1).min(frames));
            raw[i] - ((prefix[b] - prefix[a]) / (b - a) as f64) as f32 + 0.5
        })
        .collect();
    // The extremum of the drift-free track next to each nominal change.
    let mut changes = Vec::with_capacity(nominal.len());
    for (k, &c) in nominal.iter().enumerate() {
        let rising_before = k % 2 == 0; // the first stroke goes towards the tip
        let lo = c.saturating_sub(2);
        let hi = (c + 2).min(frames - 1);
        let best = (lo..=hi)
            .max_by(|&a, &b| {
                let (va, vb) = if rising_before {
                    (pos[a], pos[b])
                } else {
                    (-pos[a], -pos[b])
                };
                va.total_cmp(&vb).then(b.cmp(&a))
            })
            .unwrap_or(c);
        changes.push(best);
    }
    (pos, changes)
}

/// The violinist's ten joints at frame t for bow position `bow` (px, y down, 1280 × 720).
fn violinist(t: usize, bow: f32) -> [[f32; 2]; JOINT_COUNT] {
    let ts = t as f32 / 30.0;
    let sway = 8.0 * (2.0 * std::f32::consts::PI * ts / 4.0).sin();
    let nod = 4.0 * (2.0 * std::f32::consts::PI * ts / 2.0).sin();
    let (cx, cy) = (640.0 + sway, 360.0);
    let r_shoulder = [cx - 60.0, cy - 95.0];
    let wrist = [cx - 30.0 + bow * BOW_DX, cy - 30.0 + bow * BOW_DY];
    let mid = [
        (r_shoulder[0] + wrist[0]) / 2.0,
        (r_shoulder[1] + wrist[1]) / 2.0,
    ];
    let r_elbow = [mid[0] - 40.0, mid[1] + 35.0];
    [
        [cx + sway * 0.5, cy - 160.0 + nod],  // nose
        [cx, cy - 100.0],                     // neck
        r_shoulder,                           // r_shoulder
        r_elbow,                              // r_elbow
        wrist,                                // r_wrist
        [cx + 60.0, cy - 95.0],               // l_shoulder
        [cx + 120.0, cy - 40.0],              // l_elbow
        [cx + 100.0, cy - 120.0 + nod * 0.5], // l_wrist
        [cx - 35.0, cy + 120.0],              // r_hip
        [cx + 35.0, cy + 120.0],              // l_hip
    ]
}

/// A standing bystander: the same figure, arms down, scaled and placed at `(x, y)`.
fn bystander(t: usize, x: f32, y: f32, scale: f32) -> [[f32; 2]; JOINT_COUNT] {
    let sway = 5.0 * (t as f32 / 23.0).sin();
    let rel = [
        [0.0, -160.0],
        [0.0, -100.0],
        [-55.0, -95.0],
        [-65.0, -20.0],
        [-70.0, 50.0],
        [55.0, -95.0],
        [65.0, -20.0],
        [70.0, 50.0],
        [-35.0, 120.0],
        [35.0, 120.0],
    ];
    rel.map(|[a, b]| [x + sway + a * scale, y + b * scale])
}

/// A keypoint array of `layout` from our joints with confidences (and plausible eyes/ears).
fn keypoints(
    layout: PoseLayout,
    joints: &[[f32; 2]; JOINT_COUNT],
    conf: &[f32; JOINT_COUNT],
) -> Vec<f32> {
    let mut kp = vec![0.0f32; 3 * layout.keypoint_count()];
    for j in Joint::ALL {
        let k = j.openpose_index(layout);
        let c = conf[j.index()];
        if c > 0.0 {
            kp[3 * k..3 * k + 3].copy_from_slice(&[joints[j.index()][0], joints[j.index()][1], c]);
        }
    }
    let nose = joints[0];
    let eyes_ears = match layout {
        PoseLayout::Coco18 => [14, 15, 16, 17],
        PoseLayout::Body25 => [15, 16, 17, 18],
    };
    for (i, k) in eyes_ears.into_iter().enumerate() {
        let dx = [-12.0, 12.0, -28.0, 28.0][i];
        kp[3 * k..3 * k + 3].copy_from_slice(&[nose[0] + dx, nose[1] - 10.0, 0.7]);
    }
    if layout == PoseLayout::Body25 {
        let (r, l) = (joints[8], joints[9]);
        kp[24..27].copy_from_slice(&[(r[0] + l[0]) / 2.0, (r[1] + l[1]) / 2.0, 0.8]);
    }
    kp
}

fn events(rng: &mut Rng, frames: usize, per_100: f32) -> usize {
    let expected = per_100 * frames as f32 / 100.0;
    (expected + rng.uniform() - 0.5).round().max(0.0) as usize
}

/// Generates a clip (deterministic for a given config).
pub fn generate(cfg: &SynthConfig) -> SynthClip {
    let mut rng = Rng::new(cfg.seed);
    let t_len = cfg.frames;
    let (bow, bow_changes) = bow_track(t_len, &mut rng);
    let mut truth = Array3::<f32>::zeros((t_len, JOINT_COUNT, 2));
    let mut conf = vec![[0.0f32; JOINT_COUNT]; t_len];
    for t in 0..t_len {
        let pose = violinist(t, bow[t]);
        for j in 0..JOINT_COUNT {
            truth[[t, j, 0]] = pose[j][0];
            truth[[t, j, 1]] = pose[j][1];
            conf[t][j] = 0.6 + 0.35 * rng.uniform();
        }
    }
    for _ in 0..events(&mut rng, t_len, cfg.dropouts_per_100_frames) {
        let (start, len) = (rng.int(0, t_len - 1), rng.int(1, 10));
        for _ in 0..rng.int(1, 3) {
            let j = rng.int(0, JOINT_COUNT - 1);
            for c in conf.iter_mut().skip(start).take(len) {
                c[j] = 0.0;
            }
        }
    }
    if let Some((joint, start, len)) = cfg.long_dropout {
        for c in conf.iter_mut().skip(start).take(len) {
            c[joint.index()] = 0.0;
        }
    }
    let mut absent = vec![false; t_len];
    for _ in 0..events(&mut rng, t_len, cfg.absences_per_100_frames) {
        let (start, len) = (rng.int(20, t_len.saturating_sub(21).max(20)), rng.int(1, 3));
        for a in absent.iter_mut().skip(start).take(len) {
            *a = true;
        }
    }
    let mut bystander_at = vec![None; t_len];
    if cfg.bystander {
        for _ in 0..3 {
            let (start, len) = (rng.int(0, t_len - 1), rng.int(30, 120));
            let (x, scale) = (1000.0 + 100.0 * rng.uniform(), 0.6 + 0.6 * rng.uniform());
            for (t, b) in bystander_at.iter_mut().enumerate().skip(start).take(len) {
                *b = Some(bystander(t, x, 420.0, scale));
            }
        }
    }
    let mut false_at = vec![None; t_len];
    for _ in 0..events(&mut rng, t_len, cfg.false_detections_per_100_frames) {
        let t = rng.int(0, t_len - 1);
        if absent[t] {
            continue;
        }
        let side = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
        let (dx, dy) = (
            side * (120.0 + 80.0 * rng.uniform()),
            60.0 * (rng.uniform() - 0.5),
        );
        // Larger and more confident than the performer: a score-only choice would take it.
        let pose = violinist(t, bow[t]).map(|[x, y]| {
            [
                640.0 + (x - 640.0) * 1.3 + dx,
                360.0 + (y - 360.0) * 1.3 + dy,
            ]
        });
        false_at[t] = Some(pose);
    }

    let mut people = Vec::with_capacity(t_len);
    for t in 0..t_len {
        let mut frame: Vec<Vec<f32>> = Vec::new();
        if !absent[t] {
            let mut pose = [[0.0f32; 2]; JOINT_COUNT];
            for (j, p) in pose.iter_mut().enumerate() {
                *p = [
                    truth[[t, j, 0]] + cfg.jitter_px * rng.normal(),
                    truth[[t, j, 1]] + cfg.jitter_px * rng.normal(),
                ];
            }
            frame.push(keypoints(cfg.layout, &pose, &conf[t]));
        }
        if let Some(b) = bystander_at[t] {
            let c: [f32; JOINT_COUNT] = std::array::from_fn(|_| 0.5 + 0.3 * rng.uniform());
            frame.push(keypoints(cfg.layout, &b, &c));
        }
        if let Some(f) = false_at[t] {
            frame.push(keypoints(cfg.layout, &f, &[0.97; JOINT_COUNT]));
        }
        // People come in no particular order.
        if frame.len() > 1 {
            let k = rng.int(0, frame.len() - 1);
            frame.swap(0, k);
        }
        people.push(frame);
    }
    SynthClip {
        layout: cfg.layout,
        truth,
        bow_changes,
        absent_frames: (0..t_len).filter(|&t| absent[t]).collect(),
        false_detection_frames: (0..t_len).filter(|&t| false_at[t].is_some()).collect(),
        bystander_frames: bystander_at.iter().filter(|b| b.is_some()).count(),
        people,
    }
}

/// Writes one OpenPose JSON document per frame into `dir` (created if needed) as
/// `{prefix}_{frame:012}_keypoints.json`. Every other frame carries OpenPose's full schema
/// (face/hand arrays, `pose_keypoints_3d`, an unknown field); the others only
/// `pose_keypoints_2d`, to exercise tolerant reading.
pub fn write_openpose_dir(dir: &Path, clip: &SynthClip, prefix: &str) {
    write_people_dir(dir, &clip.people, prefix);
}

/// [`write_openpose_dir`] for any frames of people (keypoint arrays).
pub fn write_people_dir(dir: &Path, frames: &[Vec<Vec<f32>>], prefix: &str) {
    std::fs::create_dir_all(dir).unwrap();
    for (t, frame) in frames.iter().enumerate() {
        let people: Vec<serde_json::Value> = frame
            .iter()
            .map(|kp| {
                if t % 2 == 0 {
                    serde_json::json!({
                        "person_id": [-1], "pose_keypoints_2d": kp,
                        "face_keypoints_2d": [], "hand_left_keypoints_2d": [1.0, 2.0, 0.5],
                        "hand_right_keypoints_2d": [], "pose_keypoints_3d": [],
                        "face_keypoints_3d": [], "hand_left_keypoints_3d": [], "hand_right_keypoints_3d": []
                    })
                } else {
                    serde_json::json!({ "pose_keypoints_2d": kp })
                }
            })
            .collect();
        let doc = if t % 2 == 0 {
            serde_json::json!({"version": 1.3, "people": people, "tracker": {"note": "unknown field"}})
        } else {
            serde_json::json!({"people": people})
        };
        let name = format!("{prefix}_{t:012}_keypoints.json");
        std::fs::write(dir.join(name), doc.to_string()).unwrap();
    }
}

/// Bow changes a 10-frame-context rule can see: at least 12 frames from either end.
pub fn detectable(changes: &[usize], frames: usize) -> Vec<usize> {
    changes
        .iter()
        .copied()
        .filter(|&c| c >= 12 && c + 12 <= frames)
        .collect()
}
