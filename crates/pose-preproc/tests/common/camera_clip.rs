//! Synthetic OpenPose clips from the project's own motion synthesis: a random performance
//! (strokes of 0.3–2 s, one note each, a melody moving by steps of up to 4 semitones) → `motion_synth::synthesize_detailed` at the clip's
//! frame rate, seen by a camera at a random yaw (−90…90°) and distance, then rolled,
//! mirrored and scaled in the image; the true bow changes are the bow planner's change
//! frames. [`super::troubles`] then adds what pose estimators do (jitter, low confidences,
//! dropouts, left/right swaps, absences, bystanders, people entering the frame).
//!
//! Seeded: the same [`ClipSpec`] always gives the same clip.

use motion_synth::geometry::Vec3;
use motion_synth::{synthesize_detailed, Camera, SynthConfig as MotionConfig};
use performance::{ArousalCurve, Performance};
use skeleton::{Joint, PoseLayout, JOINT_COUNT};

use super::troubles::{add_troubles, Troubles, View};
pub use super::troubles::{HEIGHT, WIDTH};
use super::Rng;

/// The camera and the image transform.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraSpec {
    /// Degrees from straight in front, positive towards the player's right.
    pub yaw_deg: f64,
    /// Image rotation about the image centre, degrees.
    pub roll_deg: f64,
    /// Camera distance, metres (perspective).
    pub distance_m: f64,
    /// Mirrored image (x flipped, and so the estimator's left and right swapped).
    pub mirror: bool,
    /// Height of the performer (nose to hips) in the image, pixels.
    pub height_px: f64,
    /// Frame rate.
    pub fps: f64,
}

/// Everything that defines a clip.
#[derive(Debug, Clone, PartialEq)]
pub struct ClipSpec {
    pub seed: u64,
    pub duration_s: f64,
    pub layout: PoseLayout,
    pub camera: CameraSpec,
    pub troubles: Troubles,
}

/// Kinds of camera of the evaluation sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CameraKind {
    /// Yaw −25…25°, roll ±5°, 30 fps.
    Frontal,
    /// |yaw| 60…90°, roll ±5°, 30 fps.
    Side,
    /// Any yaw, mirrored, roll 10…20° either way, performer 50 px tall, 60 fps.
    MirroredRolledSmall60,
    /// Any yaw, any roll ±20°, 25 fps.
    Any25,
    /// Everything random: yaw −90…90°, roll ±20°, mirroring, 60–400 px, 24/25/30/50/60 fps.
    Random,
}

impl CameraKind {
    pub const ALL: [CameraKind; 5] = [
        CameraKind::Frontal,
        CameraKind::Side,
        CameraKind::MirroredRolledSmall60,
        CameraKind::Any25,
        CameraKind::Random,
    ];

    pub fn name(self) -> &'static str {
        match self {
            CameraKind::Frontal => "frontal",
            CameraKind::Side => "side",
            CameraKind::MirroredRolledSmall60 => "mirrored+rolled+small 60fps",
            CameraKind::Any25 => "25 fps",
            CameraKind::Random => "random",
        }
    }
}

fn between(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * f64::from(rng.uniform())
}

fn sign(rng: &mut Rng) -> f64 {
    if rng.uniform() < 0.5 {
        -1.0
    } else {
        1.0
    }
}

impl ClipSpec {
    /// A random clip of `kind` (seeded), with the standard troubles.
    pub fn random(kind: CameraKind, seed: u64, duration_s: f64) -> ClipSpec {
        let mut rng = Rng::new(seed.wrapping_mul(0x9E37_79B9).wrapping_add(17));
        let any_yaw = between(&mut rng, -90.0, 90.0);
        let distance_m = between(&mut rng, 2.0, 6.0);
        let height = between(&mut rng, 120.0, 400.0);
        let small_roll = between(&mut rng, -5.0, 5.0);
        let camera = match kind {
            CameraKind::Frontal => CameraSpec {
                yaw_deg: between(&mut rng, -25.0, 25.0),
                roll_deg: small_roll,
                distance_m,
                mirror: false,
                height_px: height,
                fps: 30.0,
            },
            CameraKind::Side => CameraSpec {
                yaw_deg: sign(&mut rng) * between(&mut rng, 60.0, 90.0),
                roll_deg: small_roll,
                distance_m,
                mirror: false,
                height_px: height,
                fps: 30.0,
            },
            CameraKind::MirroredRolledSmall60 => CameraSpec {
                yaw_deg: any_yaw,
                roll_deg: sign(&mut rng) * between(&mut rng, 10.0, 20.0),
                distance_m,
                mirror: true,
                height_px: 50.0,
                fps: 60.0,
            },
            CameraKind::Any25 => CameraSpec {
                yaw_deg: any_yaw,
                roll_deg: between(&mut rng, -20.0, 20.0),
                distance_m,
                mirror: rng.uniform() < 0.5,
                height_px: height,
                fps: 25.0,
            },
            CameraKind::Random => CameraSpec {
                yaw_deg: any_yaw,
                roll_deg: between(&mut rng, -20.0, 20.0),
                distance_m,
                mirror: rng.uniform() < 0.5,
                height_px: between(&mut rng, 60.0, 400.0),
                fps: [24.0, 25.0, 30.0, 50.0, 60.0][rng.int(0, 4)],
            },
        };
        let layout = if rng.uniform() < 0.5 {
            PoseLayout::Body25
        } else {
            PoseLayout::Coco18
        };
        ClipSpec {
            seed,
            duration_s,
            layout,
            camera,
            troubles: Troubles::standard(),
        }
    }
}

/// A generated clip.
pub struct CameraClip {
    pub spec: ClipSpec,
    /// True bow changes, seconds.
    pub bow_changes_s: Vec<f64>,
    /// The performer's true 2-D joints per frame (after the camera, before troubles).
    pub truth: Vec<[[f32; 2]; JOINT_COUNT]>,
    /// `people[t]`: keypoint arrays (layout count × 3) of the people of frame t.
    pub people: Vec<Vec<Vec<f32>>>,
}

/// A random performance: strokes of 0.3–2 s with one note each (a random walk of −4…+4
/// semitones in G3…E6, so string crossings are as frequent as in a melody), beats every 0.5 s, a
/// downbeat every 2 s, a random-walk arousal.
pub fn random_performance(rng: &mut Rng, duration_s: f64) -> Performance {
    let mut builder = Performance::builder(duration_s);
    let mut changes = Vec::new();
    let mut t = 0.0;
    let mut midi = rng.int(60, 80) as i64;
    while t < duration_s {
        let len = between(rng, 0.3, 2.0);
        let end = (t + len).min(duration_s);
        // A melody moves mostly by steps: −4…+4 semitones, kept in G3…E6.
        midi = (midi + rng.int(0, 8) as i64 - 4).clamp(55, 88);
        builder = builder.note(t, end, midi as u8);
        if end < duration_s {
            changes.push(end);
        }
        t = end;
    }
    let beats: Vec<f64> = (0..(duration_s / 0.5) as usize)
        .map(|k| k as f64 * 0.5)
        .collect();
    let downbeats: Vec<f64> = beats.iter().copied().step_by(4).collect();
    let mut a = 0.0f32;
    let arousal: Vec<f32> = (0..(2.0 * duration_s).ceil() as usize)
        .map(|_| {
            a = (a + 0.2 * (rng.uniform() - 0.5)).clamp(-0.9, 0.9);
            a
        })
        .collect();
    builder
        .bow_changes(changes)
        .beats(beats)
        .downbeats(downbeats)
        .arousal(ArousalCurve::deam(arousal))
        .build()
        .expect("a valid performance")
}

/// The image transform: scale about the upper body's centre to `height_px`, roll, mirror,
/// and place the performer at `centre`.
struct ImageTransform {
    scale: f64,
    from: [f64; 2],
    to: [f64; 2],
    cos: f64,
    sin: f64,
    mirror: bool,
}

impl ImageTransform {
    fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        let (x, y) = (
            (p[0] - self.from[0]) * self.scale,
            (p[1] - self.from[1]) * self.scale,
        );
        let (x, y) = (x * self.cos - y * self.sin, x * self.sin + y * self.cos);
        let x = if self.mirror { -x } else { x };
        [self.to[0] + x, self.to[1] + y]
    }
}

/// The performer's joint indices with left and right exchanged (for mirrored images).
fn mirrored_label(j: usize) -> usize {
    let swap = |a: Joint, b: Joint| (a.index(), b.index());
    for (a, b) in [
        swap(Joint::RShoulder, Joint::LShoulder),
        swap(Joint::RElbow, Joint::LElbow),
        swap(Joint::RWrist, Joint::LWrist),
        swap(Joint::RHip, Joint::LHip),
    ] {
        if j == a {
            return b;
        }
        if j == b {
            return a;
        }
    }
    j
}

/// Generates a clip (deterministic for a given spec).
pub fn generate_clip(spec: &ClipSpec) -> CameraClip {
    let mut rng = Rng::new(spec.seed);
    let perf = random_performance(&mut rng, spec.duration_s);
    let cam = &spec.camera;
    let camera = Camera::orbit(WIDTH as u32, HEIGHT as u32, cam.yaw_deg, cam.distance_m);
    let cfg = MotionConfig {
        fps: cam.fps,
        camera: camera.clone(),
        ..Default::default()
    };
    let synth = synthesize_detailed(&perf, &cfg).expect("synthesis");
    let frames = synth.motion.frames();
    let n = synth.motion.len();
    // Scale so that nose-to-hips spans `height_px`, about the mean upper-body point.
    let (nose, hip) = (Joint::Nose.index(), Joint::RHip.index());
    let span = (0..n)
        .map(|t| f64::from(frames[[t, hip, 1]] - frames[[t, nose, 1]]).abs())
        .sum::<f64>()
        / n.max(1) as f64;
    let mean = |c: usize| {
        frames
            .iter()
            .skip(c)
            .step_by(2)
            .map(|&v| f64::from(v))
            .sum::<f64>()
            / (n * JOINT_COUNT).max(1) as f64
    };
    let roll = cam.roll_deg.to_radians();
    let margin = cam.height_px;
    let tf = ImageTransform {
        scale: cam.height_px / span.max(1.0),
        from: [mean(0), mean(1)],
        to: [
            between(
                &mut rng,
                margin.min(WIDTH / 2.0),
                (WIDTH - margin).max(WIDTH / 2.0),
            ),
            between(
                &mut rng,
                (0.8 * margin).min(HEIGHT / 2.0),
                (HEIGHT - 0.8 * margin).max(HEIGHT / 2.0),
            ),
        ],
        cos: roll.cos(),
        sin: roll.sin(),
        mirror: cam.mirror,
    };
    // Depth of every joint relative to the neck, for occlusion of the far side.
    let depth = synth.motion.frames_3d().map(|f3| {
        (0..n)
            .map(|t| {
                let d = |j: usize| {
                    let p = Vec3::new(
                        f64::from(f3[[t, j, 0]]),
                        f64::from(f3[[t, j, 1]]),
                        f64::from(f3[[t, j, 2]]),
                    );
                    (p - camera.eye).length()
                };
                let neck = d(Joint::Neck.index());
                std::array::from_fn::<f32, JOINT_COUNT, _>(|j| (d(j) - neck) as f32)
            })
            .collect::<Vec<_>>()
    });
    let mut truth = Vec::with_capacity(n);
    let mut behind = Vec::with_capacity(n);
    for t in 0..n {
        let mut pose = [[0.0f32; 2]; JOINT_COUNT];
        let mut far = [0.0f32; JOINT_COUNT];
        for j in 0..JOINT_COUNT {
            let p = tf.apply([f64::from(frames[[t, j, 0]]), f64::from(frames[[t, j, 1]])]);
            let label = if cam.mirror { mirrored_label(j) } else { j };
            pose[label] = [p[0] as f32, p[1] as f32];
            far[label] = depth.as_ref().map_or(0.0, |d| d[t][j]);
        }
        truth.push(pose);
        behind.push(far);
    }
    let bow_changes_s = synth
        .bow
        .change_frames()
        .iter()
        .map(|&f| f as f64 / cam.fps)
        .collect();
    let view = View {
        fps: cam.fps,
        height_px: cam.height_px,
        yaw_deg: cam.yaw_deg,
        layout: spec.layout,
    };
    let people = add_troubles(&truth, &behind, &spec.troubles, &view, &mut rng);
    CameraClip {
        spec: spec.clone(),
        bow_changes_s,
        truth,
        people,
    }
}
