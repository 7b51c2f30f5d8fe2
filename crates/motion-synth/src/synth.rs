//! [`synthesize`]: a [`Performance`] → a [`Motion`] (3-D rig, 2-D pixels, instrument).

use ndarray::Array3;
use skeleton::{InstrumentPoint, Motion, PerformerPart, PerformerTrack, JOINT_COUNT};

use crate::body::{body_track, BodyConfig, BodyTrack};
use crate::bow::{change_frames, plan_bow, plan_bow_directed, BowPlan, BowPolicy};
use crate::camera::Camera;
use crate::error::{Result, SynthError};
use crate::left_hand::{
    bowed_string_events, glide_track, left_hand_tracks, resolve_fingerings, second_voice,
    LeftHandConfig,
};
use crate::performer::{finger_plan, FingerFrame, PerformerBuilder};
use crate::rig::{PoseInput, Rig};
use performance::BowStroke;
use performance::Performance;

/// Everything [`synthesize`] can be tuned with; the default is the product's.
#[derive(Debug, Clone, PartialEq)]
pub struct SynthConfig {
    /// Output frame rate (30).
    pub fps: f64,
    /// The body, violin and bow.
    pub rig: Rig,
    /// The camera that makes the 2-D track.
    pub camera: Camera,
    /// The bow planner's rules.
    pub bow: BowPolicy,
    /// Torso tilt and head sway.
    pub body: BodyConfig,
    /// Left-hand shifts and string crossings.
    pub left_hand: LeftHandConfig,
}

impl Default for SynthConfig {
    fn default() -> Self {
        SynthConfig {
            fps: 30.0,
            rig: Rig::default(),
            camera: Camera::default(),
            bow: BowPolicy::default(),
            body: BodyConfig::default(),
            left_hand: LeftHandConfig::default(),
        }
    }
}

impl SynthConfig {
    fn validate(&self) -> Result<()> {
        if !(self.fps.is_finite() && self.fps > 0.0 && self.fps <= 1000.0) {
            return Err(SynthError::InvalidConfig(format!(
                "fps {} must be in (0, 1000]",
                self.fps
            )));
        }
        if !self.camera.is_valid() {
            return Err(SynthError::InvalidConfig(
                "camera: needs a non-zero image, a positive focal length and an eye apart from the target, not straight above or below it".into(),
            ));
        }
        if !self.body.is_valid() {
            return Err(SynthError::InvalidConfig(
                "body: angles must be finite, forward shares in (0, 1), default_bar_s > 0".into(),
            ));
        }
        if !self.left_hand.is_valid() {
            return Err(SynthError::InvalidConfig(
                "left hand: glide times must be finite and >= 0".into(),
            ));
        }
        Ok(())
    }
}

/// The motion together with the tracks it was made from (for metrics and debugging).
#[derive(Debug, Clone)]
pub struct Synthesis {
    /// The skeleton: 2-D pixels, 3-D metres, instrument points, image size.
    pub motion: Motion,
    /// The planned bow strokes and positions.
    pub bow: BowPlan,
    /// Arousal, torso tilt and head sway per frame.
    pub body: BodyTrack,
    /// Bowed string per frame (0 = G … 3 = E, gliding on crossings).
    pub string_index: Vec<f64>,
    /// Left hand's place per frame, semitones from the nut.
    pub hand_semitones: Vec<f64>,
    /// Frames where a wrist could not reach its target (0 with the default rig).
    pub unreached_frames: usize,
    /// What the left fingers do per frame (which one is down where, which prepares).
    pub fingers: Vec<FingerFrame>,
}

/// Turns a performance into a 30 fps (by default) violinist skeleton: the bow planner
/// drives the right arm, the fingerings the left arm and the bowed string, arousal and
/// downbeats the torso and head (see the crate documentation). Notes without fingering are
/// planned with [`fingering::OptimalPlanner`]. Deterministic.
///
/// ```
/// use motion_synth::{synthesize, SynthConfig};
/// use performance::Performance;
/// let perf = Performance::builder(2.0).note(0.0, 1.0, 67).note(1.0, 2.0, 74)
///     .bow_changes(vec![1.0]).build()?;
/// let motion = synthesize(&perf, &SynthConfig::default())?;
/// assert_eq!(motion.len(), 60);
/// assert!(motion.max_bone_length_cv() < 1e-4);
/// # Ok::<(), motion_synth::SynthError>(())
/// ```
pub fn synthesize(perf: &Performance, cfg: &SynthConfig) -> Result<Motion> {
    Ok(synthesize_detailed(perf, cfg)?.motion)
}

/// The stroke in progress at `t_s` (the last one starting at or before it, else the first).
fn stroke_at(strokes: &[BowStroke], t_s: f64) -> BowStroke {
    let i = strokes.partition_point(|s| s.start_s <= t_s);
    strokes[i.saturating_sub(1)]
}

/// [`synthesize`], also returning the intermediate tracks.
pub fn synthesize_detailed(perf: &Performance, cfg: &SynthConfig) -> Result<Synthesis> {
    cfg.validate()?;
    let fps = cfg.fps;
    let frames = perf.frame_count(fps);

    let changes = change_frames(perf.bow_changes_s(), fps, frames);
    let downbeat_frames: Vec<f64> = perf.downbeats_s().iter().map(|t| t * fps).collect();
    let strokes = perf.bow_strokes();
    let bow = if strokes.is_empty() {
        plan_bow(&changes, frames, &downbeat_frames, &cfg.bow)?
    } else {
        plan_bow_directed(
            &changes,
            frames,
            |f| stroke_at(strokes, f as f64 / fps).direction,
            &cfg.bow,
        )?
    };
    let body = body_track(perf, fps, frames, &cfg.body);
    let fingerings = resolve_fingerings(perf.notes())?;
    let mut string_index = vec![0.0; frames];
    let mut hand_semitones = vec![0.0; frames];
    let second = second_voice(perf.notes(), &fingerings, perf.double_stops());
    left_hand_tracks(
        perf.notes(),
        &fingerings,
        &second,
        fps,
        &cfg.left_hand,
        &mut string_index,
        &mut hand_semitones,
    );
    if strokes.iter().any(|s| s.string.is_some()) {
        // The bow plays the string the stroke network heard, where it heard one.
        let notes = perf.notes();
        let heard = |i: usize| {
            let n = &notes[i];
            let own = fingerings.get(i).map(|f| f.string);
            strokes
                .iter()
                .find(|s| s.start_s <= n.onset_s + 0.05 && n.onset_s < s.end_s)
                .and_then(|s| s.string)
                .or(own)
                .map_or(0.0, |s| f64::from(s.number() - 1))
        };
        let events = bowed_string_events(notes, &second, heard);
        glide_track(
            &events,
            cfg.left_hand.string_crossing_s,
            fps,
            &mut string_index,
        );
    }

    let mut joints_2d = Array3::<f32>::zeros((frames, JOINT_COUNT, 2));
    let mut joints_3d = Array3::<f32>::zeros((frames, JOINT_COUNT, 3));
    let points = InstrumentPoint::ALL.len();
    let mut inst_2d = Array3::<f32>::zeros((frames, points, 2));
    let mut inst_3d = Array3::<f32>::zeros((frames, points, 3));
    let project = cfg.camera.projector();
    let mut unreached_frames = 0;
    let fingers = finger_plan(perf.notes(), &fingerings, &second, fps, frames);
    let flex = flex_track(&bow.change_frames(), frames, fps);
    let mut builder = PerformerBuilder::new(fps);
    let shape =
        |part: PerformerPart, dims: usize| Array3::<f32>::zeros((frames, part.point_count(), dims));
    let mut perf_2d = PerformerPart::ALL.map(|p| shape(p, 2));
    let mut perf_3d = PerformerPart::ALL.map(|p| shape(p, 3));
    for f in 0..frames {
        let input = PoseInput {
            torso_pitch_rad: body.torso_pitch_rad[f],
            head_pitch_rad: body.head_pitch_rad[f],
            bow_position: f64::from(bow.positions()[f]),
            string_index: string_index[f],
            hand_semitones: hand_semitones[f],
            hip_shift_m: body.hip_shift_m[f],
            hip_roll_rad: body.hip_roll_rad[f],
            right_flex: flex[f],
        };
        let pose = cfg.rig.pose(&input);
        if !pose.reached {
            unreached_frames += 1;
        }
        for (j, p) in pose.joints.iter().enumerate() {
            let [x, y] = project(*p);
            joints_2d[[f, j, 0]] = x as f32;
            joints_2d[[f, j, 1]] = y as f32;
            for (c, v) in p.to_array().into_iter().enumerate() {
                joints_3d[[f, j, c]] = v as f32;
            }
        }
        let whole = builder.frame(
            &cfg.rig,
            &pose,
            &fingers[f],
            string_index[f],
            hand_semitones[f],
        );
        let groups: [&[crate::geometry::Vec3]; 4] = [
            &whole.body,
            &whole.left_hand,
            &whole.right_hand,
            &whole.instrument,
        ];
        for (g, points) in groups.into_iter().enumerate() {
            for (k, p) in points.iter().enumerate() {
                let [x, y] = project(*p);
                perf_2d[g][[f, k, 0]] = x as f32;
                perf_2d[g][[f, k, 1]] = y as f32;
                for (c, v) in p.to_array().into_iter().enumerate() {
                    perf_3d[g][[f, k, c]] = v as f32;
                }
            }
        }
        for (i, p) in pose.instrument.iter().enumerate() {
            let [x, y] = project(*p);
            inst_2d[[f, i, 0]] = x as f32;
            inst_2d[[f, i, 1]] = y as f32;
            for (c, v) in p.to_array().into_iter().enumerate() {
                inst_3d[[f, i, c]] = v as f32;
            }
        }
    }
    let motion = Motion::new(fps, joints_2d)?
        .with_3d(joints_3d)?
        .with_instrument(inst_2d)?
        .with_instrument_3d(inst_3d)?
        .with_performer(PerformerTrack::new(perf_2d)?.with_3d(perf_3d)?)?
        .with_image_size(cfg.camera.width_px, cfg.camera.height_px);
    Ok(Synthesis {
        motion,
        bow,
        body,
        string_index,
        hand_semitones,
        unreached_frames,
        fingers,
    })
}

/// Right-hand finger flexion per frame: a bump of 0.15 s half-width around each bow change.
fn flex_track(changes: &[usize], frames: usize, fps: f64) -> Vec<f64> {
    let mut flex = vec![0.0; frames];
    let half = (0.15 * fps).max(1.0);
    let reach = (3.0 * half).ceil() as usize;
    for &c in changes {
        for (f, slot) in flex
            .iter_mut()
            .enumerate()
            .take((c + reach).min(frames))
            .skip(c.saturating_sub(reach))
        {
            let d = (f as f64 - c as f64) / half;
            *slot = f64::max(*slot, (-d * d).exp());
        }
    }
    flex
}
